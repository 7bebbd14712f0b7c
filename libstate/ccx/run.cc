#include "ccx/run.h"

#include "ccx/deck.h"
#include "util/error.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace hapstate {
namespace {

// Single-quoted for /bin/sh.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

bool log_reports_error(const std::filesystem::path& log) {
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);) {
    if (line.find("*ERROR") != std::string::npos) return true;
  }
  return false;
}

}  // namespace

void run_ccx(const std::filesystem::path& dir) {
  if (!std::filesystem::exists(dir / kCcxDeckFile)) {
    throw InputError("no CalculiX deck " + (dir / kCcxDeckFile).string());
  }
  const char* env = std::getenv("HAPSTATE_CCX");
  const std::string exe = env != nullptr && *env != '\0' ? env : "ccx";
  const std::filesystem::path log = dir / "ccx.log";
  std::filesystem::remove(dir / (std::string(kCcxJobName) + ".dat"));
  // OMP_NUM_THREADS=1: ccx is small here and the machine is shared.
  const std::string cmd = "cd " + shell_quote(dir.string()) + " && OMP_NUM_THREADS=1 " +
                          shell_quote(exe) + " -i " + kCcxJobName + " > ccx.log 2>&1";
  const int rc = std::system(cmd.c_str());
  if (rc != 0 || log_reports_error(log)) {
    std::ostringstream m;
    m << "CalculiX (" << exe << ") failed in " << dir.string() << " (status " << rc << "); see "
      << log.string();
    if (rc == 127 * 256) m << " -- is calculix-ccx installed?";
    throw InputError(m.str());
  }
}

}  // namespace hapstate
