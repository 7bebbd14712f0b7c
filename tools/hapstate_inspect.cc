// hapstate-inspect: read-only reports over a state directory (docs/inspect.md). A thin main:
// options, one call into libstate/maintenance, the report on stdout.
#include "maintenance/inspect.h"
#include "util/main_guard.h"

#include "help_format.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace hapstate {
namespace {

struct Options {
  std::string state;
  bool json = false;
  std::vector<int> ijk;
  long long checkpoint_id = -1;
  long long config_id = -1;
  std::string vtu;
  std::string mesh;
  std::string sql;
};

int run(const Options& o, const CLI::App& app) {
  const StateDir dir = locate_state(o.state);
  InspectOutput out;
  if (app.got_subcommand("summary")) {
    out = inspect_summary(dir);
  } else if (app.got_subcommand("checkpoint")) {
    if (o.checkpoint_id >= 0) {
      out = inspect_checkpoint(dir, CheckpointId(o.checkpoint_id));
    } else if (o.ijk.size() == 3) {
      out = inspect_checkpoint(dir, {o.ijk[0], o.ijk[1], o.ijk[2]});
    } else {
      throw InputError("checkpoint: give the grid index I J K or --id N");
    }
  } else if (app.got_subcommand("config")) {
    out = inspect_config(dir, ConfigId(o.config_id));
  } else if (app.got_subcommand("transitions")) {
    out = inspect_transitions(dir, ConfigId(o.config_id));
  } else if (app.got_subcommand("export")) {
    std::optional<std::filesystem::path> mesh;
    if (!o.mesh.empty()) mesh = o.mesh;
    out = export_config_vtu(dir, ConfigId(o.config_id), o.vtu, mesh);
  } else {
    out = inspect_sql(dir, o.sql);
  }
  const std::string& text = o.json ? out.json : out.text;
  std::fwrite(text.data(), 1, text.size(), stdout);
  return kExitOk;
}

}  // namespace
}  // namespace hapstate

int main(int argc, char** argv) {
  using namespace hapstate;
  Options o;
  CLI::App app{
      "hapstate-inspect: read-only reports over a state directory (catalogue.sqlite + blobs/).\n"
      "Nothing in the state directory is changed (SQLite may refresh its shared-memory index "
      "catalogue.sqlite-shm). Output is text, or one JSON document "
      "with --json (shapes in docs/inspect.md).\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input (usage, missing state directory, unknown "
      "id, refused SQL)."};
  use_hapstate_help(app, true);
  app.fallthrough();  // --state / --json may also follow the command
  app.require_subcommand(1);
  app.add_option("--state", o.state, "state directory")->required();
  app.add_flag("--json", o.json, "machine-readable output: one JSON document on stdout");

  app.add_subcommand(
      "summary",
      "counts per stage and last runs, check-points by class, configurations, "
      "levels per check-point, transitions by outcome, failures by reason, disk use");
  auto* checkpoint =
      app.add_subcommand("checkpoint", "one check-point and its configurations (levels)");
  auto* ijk = checkpoint->add_option("ijk", o.ijk, "grid index I J K")->expected(3);
  checkpoint
      ->add_option("--id", o.checkpoint_id, "check-point id instead of I J K (default: give I J K)")
      ->check(non_negative())
      ->excludes(ijk);
  auto* config = app.add_subcommand("config", "one configuration in detail");
  config->add_option("id", o.config_id, "configuration id")->required()->check(non_negative());
  auto* transitions = app.add_subcommand("transitions", "the 26 directions of a configuration");
  transitions->add_option("id", o.config_id, "configuration id")->required()->check(non_negative());
  auto* exporter = app.add_subcommand("export", "a configuration's mesh and displacement as VTU");
  exporter->add_option("id", o.config_id, "configuration id")->required()->check(non_negative());
  exporter
      ->add_option("--vtu", o.vtu,
                   "output .vtu file: the mesh as drawn with point data 'displacement' "
                   "(ParaView: Warp By Vector, scale 1)")
      ->required();
  exporter->add_option("--mesh", o.mesh,
                       "mesh file (default: the scene's mesh, relative to the state directory "
                       "or its parent; checked against the stored mesh hash)");
  auto* sql = app.add_subcommand("sql",
                                 "one read-only SQL statement on the catalogue "
                                 "(writes, ATTACH, PRAGMA assignments are refused)");
  sql->add_option("statement", o.sql, "e.g. \"SELECT count(*) FROM configuration\"")->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return exit_after_parse_error(app, e, "hapstate-inspect");  // --help is not an error
  }
  return guarded_main("hapstate-inspect", [&] { return run(o, app); });
}
