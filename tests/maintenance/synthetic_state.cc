#include "synthetic_state.h"

#include "blobs/segment_writer.h"
#include "catalogue/catalogue.h"
#include "catalogue/transaction.h"

#include <map>
#include <random>

namespace hapstate::test_util {
namespace {

struct Vectors {
  std::vector<double> u, t, h;
};

std::vector<double> random_vector(std::size_t n, unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> dist(-scale, scale);
  std::vector<double> v(n);
  for (double& x : v) x = dist(rng);
  return v;
}

// Vectors of configurations 2..8 (1 is the zero state without a blob).
std::map<int, Vectors> make_vectors() {
  const std::size_t n = 3 * kLiverNodes;
  std::map<int, Vectors> v;
  v[2] = {random_vector(n, 2, 0.1), {0.1, 0, 0}, {1.0, 0.2, -0.3}};
  v[3] = {random_vector(n, 3, 0.1), {0.2, 0, 0}, {0.4, 0.1, 0.0}};
  v[4] = v[3];
  v[4].u[0] += 0.5 * kUTol;  // 0.5 tolerances
  v[4].h[1] += 0.3 * kHTol;
  v[5] = v[3];
  v[5].u[7] -= 1.05 * kUTol;  // just outside
  v[6] = {random_vector(n, 6, 0.1), {0.3, 0, 0}, {0.7, -0.2, 0.1}};
  v[7] = v[6];
  v[7].h[0] += 1.01 * kHTol;  // just outside, by the reaction
  v[8] = v[6];
  v[8].h[2] -= 0.99 * kHTol;  // just inside
  return v;
}

// u at the sample nodes 0, 90 and 180, as the expand stage's LevelSketch stores it.
std::vector<double> summary_of(const std::vector<double>& u) {
  std::vector<double> s;
  for (int node : {0, 90, 180}) {
    for (int a = 0; a < 3; ++a) s.push_back(u[3 * node + a]);
  }
  return s;
}

std::string scene_text() {
  return "[mesh]\nfile = \"" + liver_mesh().string() +
         "\"\nunit = 0.01\n\n[material]\nlaw = \"neohooke\"\nyoung = 5000.0\npoisson = 0.45\n\n"
         "[probe]\nmode = \"grab\"\npoint = [-2.5, 3.5, 2.2]\nmax_force = 3.0\n\n"
         "[grid]\nspacing = 0.25\n\n[levels]\ndisplacement_tolerance = 0.01\nforce_tolerance = "
         "0.05\n";
}

}  // namespace

std::filesystem::path liver_mesh() {
  return std::filesystem::path(HAPSTATE_TEST_DATA) / "meshes/liver.msh";
}

std::vector<double> synthetic_u(int id) {
  if (id == 1) return {};
  return make_vectors().at(id).u;
}

void write_synthetic_state(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir / "blobs");
  Catalogue cat(dir / "catalogue.sqlite", OpenMode::kCreate);
  SceneRecord scene;
  scene.text = scene_text();
  scene.hash = content_hash(scene.text);
  scene.mesh_file = liver_mesh().string();
  scene.mesh_hash = content_hash_file(liver_mesh());
  scene.mesh_nodes = kLiverNodes;
  scene.mesh_elements = 596;
  cat.write_scene(scene);

  const auto run = [&](const char* stage, StageOutcome outcome, const char* message) {
    StageRun r;
    r.stage = stage;
    r.inputs = {{"scene", scene.hash}};
    r.started = TimeMs(std::chrono::milliseconds(1700000000000));
    r.ended = r.started + std::chrono::milliseconds(1500);
    r.outcome = outcome;
    r.message = message;
    cat.insert_stage_run(r);
  };
  run("import", StageOutcome::kOk, "imported");
  run("grid", StageOutcome::kOk, "4 check-points");
  run("expand", StageOutcome::kPartial, "stopped by --max-transitions");

  const std::map<int, Vectors> vectors = make_vectors();
  // Segment of each configuration's vectors: 1 {2, 3}, 2 {4, 5, 6}, 3 {7, 8}.
  const std::map<int, int> segment_of = {{2, 1}, {3, 1}, {4, 2}, {5, 2}, {6, 2}, {7, 3}, {8, 3}};
  for (int s = 1; s <= 3; ++s) {
    SegmentWriter w(dir / "blobs", SegmentId{s}, SegmentProvenance{scene.hash.hex(), "", "expand"});
    for (const auto& [id, seg] : segment_of) {
      if (seg != s) continue;
      const std::string g = "c" + std::to_string(id);
      w.write(g + "/u", vectors.at(id).u);
      w.write(g + "/t", vectors.at(id).t);
      w.write(g + "/h", vectors.at(id).h);
      if (id == 3) w.write(g + "/visual", std::vector<float>{0.5f, -1.25f, 3.0f});
    }
    w.close();
  }

  Transaction tx(cat);
  const std::array<std::array<int, 3>, 4> ijk = {{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}}};
  for (std::size_t i = 0; i < ijk.size(); ++i) {
    Checkpoint c;
    c.ijk = ijk[i];
    c.position = {0.25 * ijk[i][0], 0.25 * ijk[i][1], 0.25 * ijk[i][2]};
    c.classification = i < 3 ? CheckpointClass::kWorkspace : CheckpointClass::kOutsideWorkspace;
    cat.insert_checkpoint(c);  // ids 1..4
  }
  // (checkpoint, level, wave) of configurations 1..8.
  const std::array<std::array<int, 3>, 8> where = {
      {{1, 0, 0}, {1, 1, 1}, {2, 0, 1}, {2, 1, 2}, {2, 2, 2}, {3, 0, 2}, {3, 1, 3}, {3, 2, 3}}};
  for (int id = 1; id <= 8; ++id) {
    Configuration c;
    c.id = ConfigId(id);
    c.checkpoint = CheckpointId(where[id - 1][0]);
    c.level = Level(where[id - 1][1]);
    c.wave = where[id - 1][2];
    if (id > 1) {
      const auto& h = vectors.at(id).h;
      c.force = {h[0], h[1], h[2]};
      c.blob = BlobRef{SegmentId{segment_of.at(id)}, "c" + std::to_string(id)};
    }
    for (int a = 0; a < 9; ++a) c.stiffness[a] = a % 4 == 0 ? 10.0 + id : 0.5;
    c.expandable = true;
    c.summary = summary_of(id == 1 ? std::vector<double>(3 * kLiverNodes, 0.0) : vectors.at(id).u);
    cat.insert_configuration(c);
  }
  const auto reached = [&](int source, int direction, int target) {
    Transition t;
    t.source = ConfigId(source);
    t.direction = Direction(direction);
    t.outcome = TransitionOutcome::kReached;
    t.target = ConfigId(target);
    t.substeps = 4;
    t.newton_iterations = 10 + source;
    t.final_residual = 1e-9;
    t.wall_ms = 2.5;
    cat.insert_transition(t);
  };
  const auto other = [&](int source, int direction, TransitionOutcome outcome, const char* reason) {
    Transition t;
    t.source = ConfigId(source);
    t.direction = Direction(direction);
    t.outcome = outcome;
    t.substeps = outcome == TransitionOutcome::kFailed ? 8 : 0;
    t.newton_iterations = outcome == TransitionOutcome::kFailed ? 240 : 0;
    t.final_residual = outcome == TransitionOutcome::kFailed ? 0.3 : 0.0;
    t.wall_ms = 1.0;
    t.failure_reason = reason;
    cat.insert_transition(t);
  };
  reached(1, 21, 3);
  reached(2, 21, 4);
  other(2, 13, TransitionOutcome::kFailed, "newton diverged");
  reached(3, 21, 6);
  reached(4, 21, 8);
  other(4, 13, TransitionOutcome::kOutsideGrid, "");
  reached(5, 4, 1);
  reached(6, 4, 4);
  other(7, 4, TransitionOutcome::kFailed, "newton diverged");
  reached(8, 4, 3);
  tx.commit();
}

}  // namespace hapstate::test_util
