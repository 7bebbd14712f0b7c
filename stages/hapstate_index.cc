// hapstate-index: the playback file of an expanded state directory (docs/playback.md).
#include "index/index_stage.h"
#include "util/main_guard.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <map>

int main(int argc, char** argv) {
  using namespace hapstate;
  IndexOptions options;
  std::string state, output;
  CLI::App app{
      "hapstate-index: write the playback file of a state directory: grid, forces, haptic "
      "stiffness, transitions and the displacements of the view nodes (float32), memory-mappable "
      "by the runtime (include/hapstate/playback.h). Skips when the file is up to date.\n"
      "Exit codes: 0 written or unchanged; 1 internal error; 2 bad options or state directory "
      "(not expanded, inconsistent): an existing playback file is left intact."};
  app.add_option("--state", state, "state directory (after hapstate-expand)")->required();
  app.add_option("-o,--output", output, "playback file (default <state>/playback.bin)");
  app.add_option("--nodes", options.view,
                 "whose displacements to store: surface (for the viewer) or all (for hapstate-eval's "
                 "all-node error)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, ViewNodes>{{"surface", ViewNodes::kSurface}, {"all", ViewNodes::kAll}}));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  }
  options.state = state;
  options.output = output;
  return guarded_main("hapstate-index", [&] {
    const IndexReport r = run_index(options);
    std::printf("hapstate-index: %s (%.1f s)\n", r.message.c_str(), r.seconds);
    return kExitOk;
  });
}
