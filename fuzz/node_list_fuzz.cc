// libFuzzer harness: node-id list files ([[fixed]] nodes = "...") and probe-path CSV files.
#include "fuzz_util.h"
#include "io/probe_path.h"
#include "scene/diagnostics.h"
#include "scene/node_list.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapstate;
  const auto file = fuzz::write_scratch("fuzz.txt", data, size);
  Diagnostics diagnostics("fuzz.toml");
  read_node_ids(file, 1000, diagnostics);
  try {
    read_probe_path(file);
  } catch (const InputError&) {
  }
  return 0;
}
