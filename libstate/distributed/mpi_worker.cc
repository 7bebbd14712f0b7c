// A worker rank of the distributed expand stage (mpi_engine.h).
#include "distributed/mpi_engine.h"
#include "distributed/wire.h"

#include "scene/scene.h"
#include "statedir/stored_problem.h"
#include "statespace/expand_batch.h"
#include "statespace/probe_model.h"
#include "util/error.h"

#include <chrono>
#include <cstdio>
#include <memory>
#include <new>
#include <unordered_map>

namespace hapstate {
namespace {

using SteadyClock = std::chrono::steady_clock;

// The solvers a worker builds once from the coordinator's set-up.
struct WorkerState {
  Scene scene;
  Problem problem;
  std::unique_ptr<ProbeModel> probe;
  // The vectors of the chunk being solved, by source configuration.
  std::unordered_map<std::int64_t, const ConfigVectors*> sources;
  std::unique_ptr<TransitionSolver> solver;
  double busy_s = 0;
};

std::unique_ptr<WorkerState> set_up(const mpi::Message& m) {
  wire::Reader r(m.bytes.data(), m.bytes.size());
  const wire::Setup setup = wire::get_setup(r);
  auto state = std::make_unique<WorkerState>();
  state->scene = parse_scene(setup.scene_text, setup.scene_label, SceneParseOptions{false});
  state->problem = problem_from_vectors(setup.problem, state->scene,
                                        ContentHash{setup.problem_hash}, setup.scene_label);
  state->probe = make_probe_model(state->problem);
  WorkerState* s = state.get();
  SourceLoader loader = [s](const Configuration& c) {
    const auto it = s->sources.find(c.id.value());
    if (it == s->sources.end())
      throw std::logic_error("MPI worker: a task's source vectors are missing from its chunk");
    return *it->second;
  };
  state->solver = std::make_unique<TransitionSolver>(
      state->problem, *state->probe, std::move(loader), setup.threads, setup.algorithm);
  return state;
}

void solve_transitions(WorkerState& state, const mpi::Message& m, wire::Writer& w) {
  wire::Reader r(m.bytes.data(), m.bytes.size());
  const auto generation = r.pod<std::uint64_t>();
  const wire::TransitionChunk chunk = wire::get_transition_chunk(r);
  state.sources.clear();
  for (std::size_t k = 0; k < chunk.tasks.size(); ++k)
    state.sources[chunk.tasks[k].source.id.value()] = &chunk.sources[chunk.source_of[k]];
  const std::vector<TransitionSolve> solves = state.solver->solve(chunk.tasks);
  state.sources.clear();
  w.pod(std::uint8_t{0});
  w.pod(generation);
  w.pod<std::uint64_t>(solves.size());
  for (std::size_t k = 0; k < solves.size(); ++k) {
    w.pod(chunk.jobs[k]);
    wire::put(w, solves[k]);
  }
}

void solve_stiffnesses(WorkerState& state, const mpi::Message& m, wire::Writer& w) {
  wire::Reader r(m.bytes.data(), m.bytes.size());
  const auto generation = r.pod<std::uint64_t>();
  const wire::StiffnessChunk chunk = wire::get_stiffness_chunk(r);
  std::vector<StiffnessTask> tasks;
  for (std::size_t k = 0; k < chunk.jobs.size(); ++k)
    tasks.push_back({&chunk.vectors[k], chunk.positions[k]});
  const std::vector<StiffnessResult> results = state.solver->stiffnesses(tasks);
  w.pod(std::uint8_t{1});
  w.pod(generation);
  w.pod<std::uint64_t>(results.size());
  for (std::size_t k = 0; k < results.size(); ++k) {
    w.pod(chunk.jobs[k]);
    wire::put(w, results[k]);
  }
}

std::vector<char> error_message(std::uint8_t kind, const std::string& what) {
  wire::Writer w;
  w.pod(kind);
  w.string(what);
  return std::move(w.bytes());
}

}  // namespace

void run_mpi_worker() {
  try {
    // Results go out without waiting for rank 0 to take them (it may be storing a batch):
    // the worker goes on with its next chunk meanwhile.
    mpi::PendingSends sends;
    std::unique_ptr<WorkerState> state;
    for (;;) {
      const mpi::Message m = mpi::receive(0, &sends);
      if (m.tag == mpi::kStop) {
        sends.wait_all();
        wire::Writer w;
        w.pod(state ? state->busy_s : 0.0);
        wire::put(w, state ? state->solver->timings() : SolverTimings{});
        w.pod(peak_rss_bytes());
        mpi::send(0, mpi::kBye, w.bytes());
        return;
      }
      if (m.tag != mpi::kSetup && m.tag != mpi::kTransitions && m.tag != mpi::kStiffness)
        throw std::logic_error("unexpected message tag " + std::to_string(m.tag) + " from rank 0");
      const auto t0 = SteadyClock::now();
      // An error while working on one message is rank 0's to report (it ends the stage and
      // then stops this worker).
      try {
        if (m.tag == mpi::kSetup) {
          state = set_up(m);
          continue;
        }
        if (!state) throw std::logic_error("MPI worker: work before the set-up");
        wire::Writer reply;
        if (m.tag == mpi::kTransitions) {
          solve_transitions(*state, m, reply);
        } else {
          solve_stiffnesses(*state, m, reply);
        }
        state->busy_s += std::chrono::duration<double>(SteadyClock::now() - t0).count();
        reply.pod(state->busy_s);
        wire::put(reply, state->solver->timings());
        sends.post(0, mpi::kResult, std::move(reply.bytes()));
      } catch (const InputError& e) {
        sends.post(0, mpi::kError, error_message(1, e.what()));
      } catch (const EnvironmentError& e) {
        sends.post(0, mpi::kError, error_message(2, e.what()));
      } catch (const std::bad_alloc&) {
        sends.post(0, mpi::kError, error_message(0, "out of memory"));
      } catch (const std::exception& e) {
        sends.post(0, mpi::kError, error_message(0, e.what()));
      }
    }
  } catch (const std::exception& e) {
    // The protocol itself failed (e.g. no memory for a message): rank 0 would wait forever.
    std::fprintf(stderr, "hapstate-expand (MPI worker): internal error: %s; ending the job\n",
                 e.what());
    mpi::abort_job(kExitFailure);
  }
}

}  // namespace hapstate
