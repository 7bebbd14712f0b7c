// hapstate-index: the playback file of an expanded state directory (docs/playback.md).
#include "hapstate/playback.h"
#include "stages/index_stage.h"
#include "util/main_guard.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <map>

int main(int argc, char** argv) {
  using namespace hapstate;
  IndexOptions options;
  std::string state, output, verify;
  CLI::App app{
      "hapstate-index: write the playback file of a state directory: grid, forces, haptic "
      "stiffness, transitions and the displacements of the view nodes (float32), memory-mappable "
      "by the runtime (include/hapstate/playback.h). Skips when the file is up to date.\n"
      "Exit codes: 0 written or unchanged; 1 internal error; 2 bad options or state directory "
      "(not expanded, inconsistent): an existing playback file is left intact."};
  use_hapstate_help(app);
  auto* state_opt = app.add_option(
      "--state", state,
      "state directory (after hapstate-expand; required unless --verify; default: none)");
  app.add_option("--verify", verify,
                 "only check an existing playback file: header, section table, every checksum and "
                 "cross-reference; print its contents (default: write one)")
      ->excludes(state_opt);
  app.add_option("-o,--output", output, "playback file (default <state>/playback.bin)");
  app.add_option("--nodes", options.view,
                 "whose displacements to store: all (default; hapstate-eval's deformation error "
                 "needs them) or surface (a smaller file for a renderer)")
      ->option_text(choices({"all", "surface"}))
      ->transform(CLI::CheckedTransformer(std::map<std::string, ViewNodes>{
          {"surface", ViewNodes::kSurface}, {"all", ViewNodes::kAll}}));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  }
  if (state.empty() && verify.empty()) {
    std::fprintf(stderr, "hapstate-index: --state (or --verify FILE) is required\n");
    return kExitBadInput;
  }
  if (!verify.empty()) {
    return guarded_main("hapstate-index", [&] {
      const PlaybackFile file(verify);
      file.verify();
      const auto d = file.grid_dims();
      const auto h = file.grid_spacing();
      std::printf(
          "%s: ok: %d configurations on a %d x %d x %d grid (spacing %g, %g, %g), %d view nodes "
          "(%s), %zu triangles, change bound %g N per unit\n",
          verify.c_str(), file.num_configurations(), d[0], d[1], d[2], h[0], h[1], h[2],
          file.num_view_nodes(), file.view_is_all_nodes() ? "all nodes" : "surface",
          file.triangles().size() / 3, file.force_change_bound());
      return kExitOk;
    });
  }
  options.state = state;
  options.output = output;
  return guarded_main("hapstate-index", [&] {
    const IndexReport r = run_index(options);
    std::printf("hapstate-index: %s (%.1f s)\n", r.message.c_str(), r.wall_s);
    return kExitOk;
  });
}
