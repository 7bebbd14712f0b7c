// hapstate-compact: the compaction stage (docs/inspect.md, "Compaction rules"). Merges
// duplicate levels, repacks the live blobs, drops garbage segments, vacuums the catalogue.
#include "maintenance/compact.h"
#include "util/main_guard.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  using namespace hapstate;
  CompactOptions options;
  bool quiet = false;
  CLI::App app{
      "hapstate-compact: compacts a state directory. Merges levels of a check-point stored twice "
      "within the scene's [levels] tolerances (the lowest id is kept, the other marked merged and "
      "every transition to it rewritten), repacks the live vectors into fewer blob segments, "
      "removes unreferenced segments and VACUUMs the catalogue. Crash-safe at any instant.\n"
      "Exit codes: 0 ok (also when there was nothing to do), 1 internal error, 2 bad input or "
      "state (missing state directory, no scene, unreadable blob)."};
  use_hapstate_help(app);
  app.add_option("--state", options.state, "state directory")->required();
  app.add_flag("--dry-run", options.dry_run, "report what would be done; change nothing");
  app.add_option("--segment-values", options.repack.max_segment_values,
                 "values per repacked segment before a new one is started (default 2^27)")
      ->check(positive());
  app.add_option("--zstd-level", options.repack.zstd_level, "zstd level of repacked segments")
      ->check(CLI::Range(1, 22));
  app.add_flag("-q,--quiet", quiet, "no progress lines (the report is still printed)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;  // --help is not an error
  }
  return guarded_main("hapstate-compact", [&] {
    options.log = quiet ? nullptr : stderr;
    const CompactReport report = run_compact(options);
    std::fputs(report.text().c_str(), stdout);
    return kExitOk;
  });
}
