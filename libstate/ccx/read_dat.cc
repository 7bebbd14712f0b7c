#include "ccx/read_dat.h"

#include "ccx/deck.h"

#include "util/error.h"
#include "util/text.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

namespace hapstate {
namespace {

// Fortran E format drops the 'E' of three-digit exponents ("1.234567-100").
bool parse_real(const std::string& token, double* v) {
  const char* begin = token.c_str();
  char* end = nullptr;
  *v = std::strtod(begin, &end);
  if (end != begin && *end == '\0') return std::isfinite(*v);
  const auto sign = token.find_last_of("+-");
  if (sign == std::string::npos || sign == 0) return false;
  const std::string fixed = token.substr(0, sign) + "E" + token.substr(sign);
  *v = std::strtod(fixed.c_str(), &end);
  return *end == '\0' && std::isfinite(*v);
}

bool is_table_of_interest(const std::string& quantity) {
  return quantity == "displacements" || quantity == "forces" || quantity == "total force";
}

// " displacements (vx,vy,vz) for set NALL and time  0.1000000E+01" -> block header.
bool parse_header(const std::string& line, CcxDatBlock* b) {
  const auto paren = line.find(" (");
  const auto set_at = line.find(" for set ");
  const auto time_at = line.find(" and time ");
  if (paren == std::string::npos || set_at == std::string::npos || time_at == std::string::npos ||
      !(paren < set_at && set_at < time_at)) {
    return false;
  }
  b->quantity = trim(line.substr(0, paren));
  b->set = trim(line.substr(set_at + 9, time_at - set_at - 9));
  return parse_real(trim(line.substr(time_at + 10)), &b->time);
}

std::string where(const std::filesystem::path& dat, int line_no) {
  return dat.string() + ":" + std::to_string(line_no) + ": ";
}

}  // namespace

std::vector<CcxDatBlock> read_ccx_dat(const std::filesystem::path& dat) {
  std::ifstream in(dat);
  if (!in) throw InputError("cannot open CalculiX output " + dat.string());
  std::vector<CcxDatBlock> blocks;
  std::string line;
  int line_no = 0;
  CcxDatBlock* open = nullptr;  // the block whose rows are being read
  std::vector<Eigen::Vector3d> rows;
  bool rows_started = false;
  auto close = [&]() {
    if (open == nullptr) return;
    open->values.resize(3, static_cast<Eigen::Index>(rows.size()));
    for (std::size_t i = 0; i < rows.size(); ++i) open->values.col(i) = rows[i];
    open = nullptr;
    rows.clear();
    rows_started = false;
  };
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty()) {
      if (rows_started) close();  // a table ends at the first blank line after its rows
      continue;
    }
    CcxDatBlock header;
    if (parse_header(line, &header)) {
      close();
      if (!is_table_of_interest(header.quantity)) continue;
      blocks.push_back(header);
      open = &blocks.back();
      continue;
    }
    if (open == nullptr) continue;  // text outside the tables we read
    std::istringstream s(t);
    std::vector<std::string> tokens;
    for (std::string tok; s >> tok;) tokens.push_back(tok);
    if (!tokens.empty() && tokens.back() == "L") {
      throw InputError(where(dat, line_no) + "values in a local system (*TRANSFORM) unsupported");
    }
    const bool total = open->quantity == "total force";
    const std::size_t want = total ? 3 : 4;
    Eigen::Vector3d v;
    bool ok = tokens.size() == want;
    for (int c = 0; ok && c < 3; ++c) ok = parse_real(tokens[want - 3 + c], &v[c]);
    if (!ok) throw InputError(where(dat, line_no) + "malformed row '" + t + "'");
    if (!total) {
      char* end = nullptr;
      const long id = std::strtol(tokens[0].c_str(), &end, 10);
      if (*end != '\0' || id < 1) throw InputError(where(dat, line_no) + "bad node id '" + t + "'");
      open->ids.push_back(static_cast<int>(id));
    }
    rows.push_back(v);
    rows_started = true;
  }
  close();
  return blocks;
}

Eigen::Matrix3Xd ccx_rest_displacement(const Problem& problem,
                                       const std::vector<CcxDatBlock>& blocks) {
  const int n = problem.mesh.num_nodes();
  const CcxDatBlock* last = nullptr;
  for (const CcxDatBlock& b : blocks)
    if (b.quantity == "displacements" && b.set == "NALL" && std::abs(b.time - 1.0) <= 1e-6)
      last = &b;
  if (last == nullptr || static_cast<int>(last->ids.size()) != n)
    throw InputError(
        "CalculiX results: no displacements of every node at the end of the rest "
        "step (time 1; ccx stopped early?)");
  Eigen::Matrix3Xd u = Eigen::Matrix3Xd::Zero(3, n);
  for (std::size_t i = 0; i < last->ids.size(); ++i) {
    if (last->ids[i] < 1 || last->ids[i] > n)
      throw InputError("CalculiX results: node id out of range");
    u.col(last->ids[i] - 1) = last->values.col(static_cast<Eigen::Index>(i)) / problem.unit;
  }
  return u;
}

std::vector<CcxPathPoint> ccx_path_results(const Problem& problem,
                                           const std::vector<CcxDatBlock>& blocks, int num_points) {
  const int n = problem.mesh.num_nodes();
  const auto& role = problem.constraints.role;
  if (static_cast<int>(role.size()) != 3 * n) {
    throw InputError("CalculiX results: constraints do not match the mesh");
  }
  // The last table of each kind printed at time k (the end of path point k's step).
  std::map<int, const CcxDatBlock*> u_at, rf_at;
  const int shift = ccx_first_point_time(problem) - 1;  // a rest step first (gravity)
  for (const CcxDatBlock& b : blocks) {
    const double k = std::round(b.time) - shift;
    if (std::abs(b.time - shift - k) > 1e-6 || k < 1 || k > num_points) continue;
    if (b.quantity == "displacements" && b.set == "NALL") u_at[static_cast<int>(k)] = &b;
    if (b.quantity == "forces" && b.set == "PROBE") rf_at[static_cast<int>(k)] = &b;
  }
  const bool has_probe = !problem.constraints.probe_nodes.empty();
  std::vector<CcxPathPoint> out(num_points);
  for (int k = 1; k <= num_points; ++k) {
    const auto u = u_at.find(k);
    if (u == u_at.end() || (has_probe && rf_at.find(k) == rf_at.end())) {
      throw InputError("CalculiX results: no output for path point " + std::to_string(k) +
                       " (ccx stopped early?)");
    }
    CcxPathPoint& pt = out[k - 1];
    pt.displacement.setZero(3, n);
    const CcxDatBlock& ub = *u->second;
    if (static_cast<int>(ub.ids.size()) != n) {
      throw InputError("CalculiX results: " + std::to_string(ub.ids.size()) +
                       " displacements for " + std::to_string(n) + " nodes at point " +
                       std::to_string(k));
    }
    for (std::size_t i = 0; i < ub.ids.size(); ++i) {
      if (ub.ids[i] > n) throw InputError("CalculiX results: node id out of range");
      pt.displacement.col(ub.ids[i] - 1) = ub.values.col(i) / problem.unit;
    }
    pt.force_on_probe_nodes.setZero();
    if (has_probe) {
      const CcxDatBlock& rb = *rf_at[k];
      for (std::size_t i = 0; i < rb.ids.size(); ++i) {
        const int node = rb.ids[i] - 1;
        if (node >= n) throw InputError("CalculiX results: node id out of range");
        for (int c = 0; c < 3; ++c) {
          // Only the DOFs the probe prescribes: a fixed component of a grabbed node carries
          // the support's reaction, not the user's.
          if (role[3 * node + c] == DofRole::kProbe) pt.force_on_probe_nodes[c] += rb.values(c, i);
        }
      }
    }
    // ccx's RF is the internal force alone; the felt force is zero at the rest state
    // (probe_body_force: the grabbed nodes' own weight, zero without gravity).
    pt.force_felt = -pt.force_on_probe_nodes + probe_body_force(problem);
  }
  return out;
}

}  // namespace hapstate
