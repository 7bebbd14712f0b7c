// Runs the real hapstate-inspect and hapstate-compact executables on a synthetic state
// directory as a user would: JSON of every command, refused SQL, exit codes and messages.
#include "../blobs/temp_dir.h"
#include "../maintenance/synthetic_state.h"
#include "catalogue/catalogue.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace hapstate {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

struct ToolRun {
  int exit_code = -1;
  std::string out, err;
};

// Runs `exe args` (args already quoted); stderr goes to a file beside the state.
ToolRun run_tool(const std::string& exe, const std::string& args, const fs::path& scratch) {
  const fs::path err_file = scratch / "stderr.txt";
  const std::string command = quote(exe) + " " + args + " 2>" + quote(err_file.string());
  ToolRun r;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  std::size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.out.append(buffer, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::ostringstream s;
  s << in.rdbuf();
  r.err = s.str();
  return r;
}

class Inspect : public ::testing::Test {
 protected:
  void SetUp() override { test_util::write_synthetic_state(state()); }
  fs::path state() const { return dir_.path() / "state"; }
  ToolRun inspect(const std::string& args) {
    return run_tool(HAPSTATE_INSPECT_EXE, "--state " + quote(state().string()) + " " + args,
                    dir_.path());
  }
  json inspect_json(const std::string& args) {
    const ToolRun r = inspect(args + " --json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return json::parse(r.out);
  }
  test_util::TempDir dir_{"inspect"};
};

TEST_F(Inspect, SummaryJson) {
  const json j = inspect_json("summary");
  EXPECT_EQ(j["schema_version"], 10);
  EXPECT_EQ(j["scene"]["mesh_nodes"], 181);
  ASSERT_EQ(j["stages"].size(), 3u);
  EXPECT_EQ(j["stages"][2]["stage"], "expand");
  EXPECT_EQ(j["stages"][2]["runs"], 1);
  EXPECT_EQ(j["stages"][2]["last"]["outcome"], "partial");
  EXPECT_EQ(j["last_runs"][0]["stage"], "expand");
  EXPECT_EQ(j["checkpoints"]["total"], 4);
  EXPECT_EQ(j["checkpoints"]["by_class"]["workspace"], 3);
  EXPECT_EQ(j["checkpoints"]["by_class"]["outside_workspace"], 1);
  EXPECT_EQ(j["configurations"]["total"], 8);
  EXPECT_EQ(j["configurations"]["open"], 8);
  EXPECT_EQ(j["configurations"]["expandable"], 8);
  EXPECT_EQ(j["configurations"]["max_wave"], 3);
  EXPECT_EQ(j["levels_per_checkpoint"],
            json::parse(R"([{"levels":0,"checkpoints":1},{"levels":2,"checkpoints":1},)"
                        R"({"levels":3,"checkpoints":2}])"));
  EXPECT_EQ(j["transitions"]["total"], 10);
  EXPECT_EQ(j["transitions"]["reached"], 7);
  EXPECT_EQ(j["transitions"]["outside_grid"], 1);
  EXPECT_EQ(j["transitions"]["failed"], 2);
  EXPECT_EQ(j["failures_by_reason"], json::parse(R"([{"reason":"newton diverged","count":2}])"));
  EXPECT_EQ(j["disk"]["segments"], 3);
  EXPECT_GT(j["disk"]["blob_bytes"].get<long long>(), 0);
  EXPECT_EQ(
      j["disk"]["total_bytes"].get<long long>(),
      j["disk"]["catalogue_bytes"].get<long long>() + j["disk"]["blob_bytes"].get<long long>());
  EXPECT_EQ(j["disk"]["problem_bytes"], 0);
}

TEST_F(Inspect, SummaryText) {
  const ToolRun r = inspect("summary");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("configurations (stored equilibrium states): 8 (0 expanded, 8 still to "
                       "expand, 0 not expanded: force above probe.max_force, 0 not expanded: "
                       "outside the workspace; 0 merged as duplicates"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("failed 2x: newton diverged"), std::string::npos) << r.out;
}

TEST_F(Inspect, CheckpointByIndexAndById) {
  const json j = inspect_json("checkpoint 1 0 0");
  EXPECT_EQ(j["checkpoint"]["id"], 2);
  EXPECT_EQ(j["checkpoint"]["class"], "workspace");
  ASSERT_EQ(j["configurations"].size(), 3u);
  EXPECT_EQ(j["configurations"][1]["id"], 4);
  EXPECT_EQ(j["configurations"][1]["level"], 1);
  EXPECT_EQ(j["configurations"][1]["transitions"], 2);
  EXPECT_DOUBLE_EQ(j["configurations"][0]["force"][0].get<double>(), 0.4);
  EXPECT_EQ(inspect_json("checkpoint --id 2"), j);
  const ToolRun missing = inspect("checkpoint 9 9 9");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("no check-point (9, 9, 9)"), std::string::npos) << missing.err;
}

TEST_F(Inspect, Config) {
  const json j = inspect_json("config 3");
  EXPECT_EQ(j["level"], 0);
  EXPECT_EQ(j["wave"], 1);
  EXPECT_EQ(j["checkpoint"]["ijk"], json::parse("[1,0,0]"));
  EXPECT_EQ(j["status"], "open");
  EXPECT_EQ(j["expandable"], true);
  EXPECT_DOUBLE_EQ(j["stiffness"][1][1].get<double>(), 13.0);
  EXPECT_EQ(j["blob"]["segment"], 1);
  EXPECT_EQ(j["blob"]["name"], "c3");
  ASSERT_EQ(j["blob"]["vectors"].size(), 4u);
  EXPECT_EQ(j["blob"]["vectors"][0], json::parse(R"({"name":"c3/h","length":3})"));
  EXPECT_EQ(j["blob"]["vectors"][1], json::parse(R"({"name":"c3/t","length":3})"));
  EXPECT_EQ(j["blob"]["vectors"][2], json::parse(R"({"name":"c3/u","length":543})"));
  EXPECT_EQ(j["transitions"]["decided"], 1);
  EXPECT_EQ(j["incoming_transitions"], 2);  // from c1 and c8
  EXPECT_TRUE(inspect_json("config 1")["blob"].is_null());
  EXPECT_EQ(inspect("config 99").exit_code, 2);
}

TEST_F(Inspect, Transitions) {
  const json j = inspect_json("transitions 4");
  ASSERT_EQ(j["transitions"].size(), 26u);
  const json& d21 = j["transitions"][21];
  EXPECT_EQ(d21["offset"], json::parse("[1,0,0]"));
  EXPECT_EQ(d21["outcome"], "reached");
  EXPECT_EQ(d21["target"], 8);
  EXPECT_EQ(d21["target_level"], 2);
  EXPECT_EQ(d21["newton_iterations"], 14);
  EXPECT_EQ(j["transitions"][13]["outcome"], "outside_grid");
  EXPECT_EQ(j["transitions"][0]["outcome"], "undecided");
  EXPECT_TRUE(j["transitions"][0]["target"].is_null());
  const json failed = inspect_json("transitions 7")["transitions"][4];
  EXPECT_EQ(failed["outcome"], "failed");
  EXPECT_EQ(failed["failure_reason"], "newton diverged");
  EXPECT_DOUBLE_EQ(failed["final_residual"].get<double>(), 0.3);
}

TEST_F(Inspect, ExportVtu) {
  const fs::path vtu = dir_.path() / "c3.vtu";
  const json j = inspect_json("export 3 --vtu " + quote(vtu.string()));
  EXPECT_EQ(j["nodes"], 181);
  EXPECT_EQ(j["tets"], 596);
  ASSERT_TRUE(fs::exists(vtu));
  std::ifstream in(vtu);
  std::ostringstream s;
  s << in.rdbuf();
  EXPECT_NE(s.str().find("NumberOfPoints=\"181\""), std::string::npos);
  EXPECT_NE(s.str().find("displacement"), std::string::npos);
  // A different mesh than the one the state was built from is refused.
  const ToolRun wrong = inspect("export 3 --vtu " + quote(vtu.string()) + " --mesh " +
                                quote(std::string(HAPSTATE_TEST_DATA) + "/meshes/bunny.msh"));
  EXPECT_EQ(wrong.exit_code, 2);
  EXPECT_NE(wrong.err.find("differs from the one the state was built from"), std::string::npos)
      << wrong.err;
}

TEST_F(Inspect, SqlReads) {
  const json j =
      inspect_json("sql " + quote("SELECT count(*) AS n, max(level) FROM configuration"));
  EXPECT_EQ(j["columns"], json::parse(R"j(["n","max(level)"])j"));
  EXPECT_EQ(j["rows"], json::parse("[[8,2]]"));
  const json s =
      inspect_json("sql " + quote("SELECT x'0102ff' AS b, NULL AS n, 2.5 AS r, 'text' AS t"));
  EXPECT_EQ(s["rows"], json::parse(R"([[{"blob":"0102ff"},null,2.5,"text"]])"));
  EXPECT_EQ(inspect("sql " + quote("SELECT x'0102ff' AS b, NULL AS n")).out,
            "b\tn\nx'0102ff'\tNULL\n");
  EXPECT_EQ(inspect_json("sql " + quote("PRAGMA user_version"))["rows"], json::parse("[[10]]"));
  // Pragmas that only read, with an argument naming a table or index.
  const json columns = inspect_json("sql " + quote("PRAGMA table_info(configuration)"));
  EXPECT_EQ(columns["columns"][1], "name");
  EXPECT_EQ(columns["rows"][0][1], "id");
  EXPECT_EQ(inspect_json("sql " + quote("pragma INTEGRITY_CHECK"))["rows"],
            json::parse(R"([["ok"]])"));
  EXPECT_FALSE(inspect_json("sql " + quote("PRAGMA index_list(transition)"))["rows"].is_null());
  EXPECT_EQ(inspect("sql " + quote("PRAGMA foreign_key_check(transition)")).exit_code, 0);
}

TEST_F(Inspect, SqlRefusesWrites) {
  const fs::path catalogue = state() / "catalogue.sqlite";
  for (const std::string& sql : std::vector<std::string>{
           "INSERT INTO checkpoint (i, j, k, x, y, z, classification) VALUES (5, 5, 5, 0, 0, 0, 1)",
           "DELETE FROM transition", "UPDATE configuration SET status = 2",
           "ATTACH DATABASE '" + (dir_.path() / "other.db").string() + "' AS other",
           "PRAGMA user_version = 7", "PRAGMA journal_mode = DELETE", "DROP TABLE transition",
           "PRAGMA user_version(7)", "PRAGMA wal_checkpoint", "PRAGMA optimize",
           "PRAGMA schema_version = 3", "BEGIN", "SELECT 1; DELETE FROM transition", "VACUUM"}) {
    const ToolRun r = inspect("sql " + quote(sql));
    EXPECT_EQ(r.exit_code, 2) << sql << "\n" << r.out << r.err;
    EXPECT_NE(r.err.find("hapstate-inspect: error:"), std::string::npos) << sql << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_.path() / "other.db"));
  Catalogue cat(catalogue, OpenMode::kReadOnly);
  EXPECT_EQ(cat.num_transitions(), 10);
  EXPECT_EQ(cat.num_checkpoints(), 4);
  EXPECT_EQ(cat.schema_version(), 10);
  EXPECT_EQ(cat.integrity_check(), "ok");
}

TEST(InspectCli, MissingStateDirectory) {
  test_util::TempDir dir("inspect");
  const ToolRun r =
      run_tool(HAPSTATE_INSPECT_EXE,
               "--state " + quote((dir.path() / "none").string()) + " summary", dir.path());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("none: no such state directory"), std::string::npos) << r.err;
  const ToolRun empty = run_tool(HAPSTATE_INSPECT_EXE,
                                 "--state " + quote(dir.path().string()) + " summary", dir.path());
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.err.find("not a state directory (no catalogue.sqlite"), std::string::npos)
      << empty.err;
  EXPECT_EQ(
      run_tool(HAPSTATE_INSPECT_EXE, "--state " + quote(dir.path().string()), dir.path()).exit_code,
      2);
  EXPECT_EQ(run_tool(HAPSTATE_INSPECT_EXE, "--help", dir.path()).exit_code, 0);
}

TEST_F(Inspect, CompactStageThenInspect) {
  const ToolRun first =
      run_tool(HAPSTATE_COMPACT_EXE, "--state " + quote(state().string()), dir_.path());
  EXPECT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.out.find(
                "2 duplicate levels merged (3 transitions redirected to the kept level, 1 moved)"),
            std::string::npos)
      << first.out;
  EXPECT_NE(first.out.find("segments: 3 -> 1"), std::string::npos) << first.out;
  const ToolRun second =
      run_tool(HAPSTATE_COMPACT_EXE, "--state " + quote(state().string()), dir_.path());
  EXPECT_EQ(second.exit_code, 0) << second.err;
  EXPECT_NE(second.out.find("nothing to do"), std::string::npos) << second.out;

  const json j = inspect_json("summary");
  EXPECT_EQ(j["configurations"]["merged"], 2);
  EXPECT_EQ(j["levels_per_checkpoint"],
            json::parse(R"([{"levels":0,"checkpoints":1},{"levels":2,"checkpoints":3}])"));
  EXPECT_EQ(j["stages"][3]["stage"], "compact");
  EXPECT_EQ(j["stages"][3]["runs"], 2);
  EXPECT_EQ(j["stages"][3]["last"]["outcome"], "unchanged");
  EXPECT_EQ(j["disk"]["segments"], 1);
  EXPECT_EQ(inspect_json("transitions 2")["transitions"][21]["target"], 3);

  const ToolRun missing = run_tool(
      HAPSTATE_COMPACT_EXE, "--state " + quote((dir_.path() / "none").string()), dir_.path());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("no such state directory"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace hapstate
