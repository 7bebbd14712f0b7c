// The messages between the expand stage's ranks carry every field: a value written and read
// back equals the original (no MPI needed), and a truncated message is an error, not garbage.
#include "distributed/wire.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace hapstate {
namespace {

ConfigVectors some_vectors(double base) {
  ConfigVectors v;
  v.u = {base, base + 1, -base};
  v.t = {0.5 * base};
  v.h = {1e-300, -2.5};
  v.touched = {3, 7, 11};
  v.multipliers = {4, 0.25};
  return v;
}

void expect_equal(const ConfigVectors& a, const ConfigVectors& b) {
  EXPECT_EQ(a.u, b.u);
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.h, b.h);
  EXPECT_EQ(a.touched, b.touched);
  EXPECT_EQ(a.multipliers, b.multipliers);
}

TEST(Wire, TransitionResultRoundTrips) {
  TransitionSolve s;
  s.solved = true;
  s.trivial = false;
  s.move.ok = false;
  s.move.failure = SolveFailure::kCutbackLimit;
  s.move.reason = "halved 8 times";
  s.move.substeps = 3;
  s.move.cutbacks = 8;
  s.move.iterations = 41;
  s.move.factorisations = 5;
  s.move.start_factorisations = 1;
  s.move.active_set_iterations = 2;
  s.move.residual = 1.25e-9;
  s.move.wall_ms = 12.5;
  s.move.residual_history = {1, 0.1, 0.001};
  s.vectors = some_vectors(2);
  s.force = {0.1, -0.2, 0.3};
  s.midpoint_force = std::array<double, 3>{0.05, -0.1, 0.15};
  s.midpoint_stiffness = std::array<double, 9>{-1, 0.2, 0, 0.2, -1.5, 0, 0, 0, -2.5};
  s.midpoint_u = {0.5f, -0.25f, 1e-7f};
  s.midpoint_du_dp = {1, 0, 0, 0, 1, 0, 0.5f, 0, 1};
  wire::Writer w;
  wire::put(w, s);
  wire::Reader r(w.bytes().data(), w.bytes().size());
  const TransitionSolve t = wire::get_transition_solve(r);
  EXPECT_TRUE(r.done());
  EXPECT_EQ(t.solved, s.solved);
  EXPECT_EQ(t.trivial, s.trivial);
  EXPECT_EQ(t.move.ok, s.move.ok);
  EXPECT_EQ(t.move.failure, s.move.failure);
  EXPECT_EQ(t.move.reason, s.move.reason);
  EXPECT_EQ(t.move.substeps, 3);
  EXPECT_EQ(t.move.cutbacks, 8);
  EXPECT_EQ(t.move.iterations, 41);
  EXPECT_EQ(t.move.factorisations, 5);
  EXPECT_EQ(t.move.start_factorisations, 1);
  EXPECT_EQ(t.move.active_set_iterations, 2);
  EXPECT_EQ(t.move.residual, s.move.residual);
  EXPECT_EQ(t.move.wall_ms, s.move.wall_ms);
  EXPECT_EQ(t.move.residual_history, s.move.residual_history);
  expect_equal(t.vectors, s.vectors);
  EXPECT_EQ(t.force, s.force);
  EXPECT_EQ(t.midpoint_force, s.midpoint_force);
  EXPECT_EQ(t.midpoint_stiffness, s.midpoint_stiffness);
  EXPECT_EQ(t.midpoint_u, s.midpoint_u);
  EXPECT_EQ(t.midpoint_du_dp, s.midpoint_du_dp);
}

TEST(Wire, TransitionChunkRoundTripsWithSharedSources) {
  wire::TransitionChunk c;
  c.sources = {some_vectors(1), some_vectors(5)};
  for (int k = 0; k < 3; ++k) {
    TransitionTask t;
    t.source.id = ConfigId(40 + (k > 0));
    if (k > 0) t.source.blob = BlobRef{SegmentId(3), "c41"};
    t.direction = Direction(7 * k);
    t.from = Eigen::Vector3d(k, 2.0, -1.5);
    t.to = Eigen::Vector3d(k + 0.5, 2.0, -1.5);
    if (k != 1) t.target = CheckpointId(100 + k);
    c.tasks.push_back(t);
    c.jobs.push_back(1000 + k);
    c.source_of.push_back(k > 0);
  }
  wire::Writer w;
  wire::put(w, c);
  wire::Reader r(w.bytes().data(), w.bytes().size());
  const wire::TransitionChunk d = wire::get_transition_chunk(r);
  EXPECT_TRUE(r.done());
  ASSERT_EQ(d.tasks.size(), 3u);
  ASSERT_EQ(d.sources.size(), 2u);
  expect_equal(d.sources[1], c.sources[1]);
  EXPECT_EQ(d.jobs, c.jobs);
  EXPECT_EQ(d.source_of, c.source_of);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(d.tasks[k].source.id, c.tasks[k].source.id);
    EXPECT_EQ(d.tasks[k].source.blob, c.tasks[k].source.blob);
    EXPECT_EQ(d.tasks[k].direction, c.tasks[k].direction);
    EXPECT_EQ(d.tasks[k].from, c.tasks[k].from);
    EXPECT_EQ(d.tasks[k].to, c.tasks[k].to);
    EXPECT_EQ(d.tasks[k].target, c.tasks[k].target);
  }
}

TEST(Wire, SetupStiffnessAndTimingsRoundTrip) {
  wire::Setup s;
  s.algorithm = SolverAlgorithm::kReference;
  s.threads = 3;
  s.scene_text = "[mesh]\nfile = \"a.msh\"\n";
  s.scene_label = "cat.sqlite (stored scene)";
  s.problem_hash = 0x0123456789abcdefULL;
  s.problem.nodes = {0, 1, 2, 3, 4, 5};
  s.problem.rest = {1, 2, 3};
  StiffnessResult k;
  for (int i = 0; i < 9; ++i) k.stiffness[i] = i - 4.5;
  k.du_dp = {0.5f, -1.25f, 3.0f, 1e-7f, 0.0f, 2.5f};
  k.factorisations = 2;
  SolverTimings t;
  t.assembly = 1.5;
  t.contact_detection = 0.25;
  t.factorisations = 17;
  t.contact_queries = 99;
  t.factor_bytes = 4e7;
  t.single_factor_bytes = 2e7;
  t.back_substitutions = 1234;
  t.single_back_substitutions = 1200;
  wire::Writer w;
  wire::put(w, s);
  wire::put(w, k);
  wire::put(w, t);
  wire::Reader r(w.bytes().data(), w.bytes().size());
  const wire::Setup s2 = wire::get_setup(r);
  const StiffnessResult k2 = wire::get_stiffness_result(r);
  const SolverTimings t2 = wire::get_timings(r);
  EXPECT_TRUE(r.done());
  EXPECT_EQ(s2.algorithm, s.algorithm);
  EXPECT_EQ(s2.threads, 3);
  EXPECT_EQ(s2.scene_text, s.scene_text);
  EXPECT_EQ(s2.scene_label, s.scene_label);
  EXPECT_EQ(s2.problem_hash, s.problem_hash);
  EXPECT_EQ(s2.problem.nodes, s.problem.nodes);
  EXPECT_EQ(s2.problem.rest, s.problem.rest);
  EXPECT_TRUE(s2.problem.tets.empty());
  EXPECT_EQ(k2.stiffness, k.stiffness);
  EXPECT_EQ(k2.du_dp, k.du_dp);
  EXPECT_EQ(k2.factorisations, 2);
  EXPECT_EQ(t2.assembly, 1.5);
  EXPECT_EQ(t2.contact_detection, 0.25);
  EXPECT_EQ(t2.factorisations, 17);
  EXPECT_EQ(t2.contact_queries, 99);
  EXPECT_EQ(t2.factor_bytes, 4e7);
  EXPECT_EQ(t2.single_factor_bytes, 2e7);
  EXPECT_EQ(t2.back_substitutions, 1234);
  EXPECT_EQ(t2.single_back_substitutions, 1200);
}

TEST(Wire, TruncatedMessageIsAnError) {
  TransitionSolve s;
  s.vectors = some_vectors(1);
  wire::Writer w;
  wire::put(w, s);
  for (std::size_t cut :
       {std::size_t{0}, std::size_t{5}, w.bytes().size() / 2, w.bytes().size() - 1}) {
    wire::Reader r(w.bytes().data(), cut);
    EXPECT_THROW(wire::get_transition_solve(r), std::runtime_error) << "cut at " << cut;
  }
}

}  // namespace
}  // namespace hapstate
