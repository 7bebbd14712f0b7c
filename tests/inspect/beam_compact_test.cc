// The real pipeline on the beam (pipelines/beam/): import, grid, expand, then hapstate-compact
// and hapstate-inspect on the result. Compaction of a fresh expansion merges nothing but
// repacks the per-batch segments into one, keeping every decision and every vector bit for
// bit; expand resumes on the compacted directory; export uses the stored mesh.
#include "../stages/beam_state.h"

#include <nlohmann/json.hpp>

#include <map>

namespace hapstate {
namespace {

using namespace test_util;
using nlohmann::json;

using VectorsById = std::map<std::int64_t, std::vector<std::vector<double>>>;

VectorsById read_vectors(const fs::path& state) {
  Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
  BlobStore blobs(state / "blobs");
  VectorsById out;
  for (const Configuration& c : cat.read_all_configurations()) {
    if (!c.blob) continue;
    for (const char* v : {"/u", "/t", "/h"})
      out[c.id.value()].push_back(blobs.read(c.blob->segment, c.blob->name + v));
  }
  return out;
}

Snapshot without_blob_layout(Snapshot s) {
  for (Configuration& c : s.configurations) c.blob.reset();
  s.segment_files.clear();
  return s;
}

class BeamCompact : public StageTest {};

TEST_F(BeamCompact, RepacksKeepsDecisionsAndVectorsThenInspects) {
  const fs::path state = dir_ / "state";
  build_beam(state, kBeamScene, 1, dir_);
  if (HasFatalFailure()) return;
  const Snapshot before = snapshot(state);
  const VectorsById vectors_before = read_vectors(state);
  ASSERT_GT(before.segment_files.size(), 1u);
  ASSERT_GT(vectors_before.size(), 10u);

  const StageResult first =
      run_stage(HAPSTATE_COMPACT_EXE, {"--state", state.string(), "-q"}, dir_);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.out.find("0 duplicate levels merged, 44 configurations repacked"),
            std::string::npos)
      << first.out;
  EXPECT_NE(first.out.find("segments: " + std::to_string(before.segment_files.size()) + " -> 1"),
            std::string::npos)
      << first.out;

  const Snapshot after = snapshot(state);
  expect_same_decisions(without_blob_layout(before), without_blob_layout(after));
  EXPECT_EQ(after.segment_files.size(), 1u);
  EXPECT_EQ(read_vectors(state), vectors_before);  // bit for bit
  {
    Catalogue cat(state / "catalogue.sqlite", OpenMode::kReadOnly);
    EXPECT_EQ(cat.integrity_check(), "ok");
    EXPECT_EQ(cat.num_foreign_key_violations(), 0);
    EXPECT_TRUE(
        BlobStore(state / "blobs").unreferenced_segments(cat.referenced_segments()).empty());
  }

  // Expand resumes on the compacted directory and changes no decision.
  const StageResult resumed = expand_stage(state, 1, dir_);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_decisions(without_blob_layout(before), without_blob_layout(snapshot(state)));

  const StageResult second =
      run_stage(HAPSTATE_COMPACT_EXE, {"--state", state.string(), "-q"}, dir_);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_NE(second.out.find("nothing to do"), std::string::npos) << second.out;

  const StageResult summary =
      run_stage(HAPSTATE_INSPECT_EXE, {"--state", state.string(), "summary", "--json"}, dir_);
  ASSERT_EQ(summary.exit_code, 0) << summary.err;
  const json j = json::parse(summary.out);
  EXPECT_EQ(j["configurations"]["total"].get<std::size_t>(), before.configurations.size());
  EXPECT_EQ(j["transitions"]["total"].get<std::size_t>(), before.transitions.size());
  EXPECT_EQ(j["disk"]["segments"], 1);
  EXPECT_GT(j["disk"]["problem_bytes"].get<long long>(), 0);
  EXPECT_EQ(j["scene"]["mesh_nodes"], 81);

  // Export the first configuration with vectors on the mesh stored by the import stage.
  const std::int64_t id = vectors_before.begin()->first;
  const fs::path vtu = dir_ / "c.vtu";
  const StageResult exported = run_stage(
      HAPSTATE_INSPECT_EXE,
      {"--state", state.string(), "export", std::to_string(id), "--vtu", vtu.string(), "--json"},
      dir_);
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const json e = json::parse(exported.out);
  EXPECT_EQ(e["nodes"], 81);
  EXPECT_TRUE(e["mesh"].get<std::string>().ends_with("problem/seg-000001.h5")) << e["mesh"];
  EXPECT_TRUE(fs::exists(vtu));
}

}  // namespace
}  // namespace hapstate
