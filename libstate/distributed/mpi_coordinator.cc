// Rank 0's side of the distributed expand stage (mpi_engine.h).
#include "distributed/mpi_engine.h"
#include "distributed/wire.h"

#include "statedir/stage_context.h"
#include "statedir/stored_problem.h"
#include "statespace/expand_batch.h"
#include "util/error.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace hapstate {
namespace {

using Clock = std::chrono::steady_clock;

bool g_workers_released = false;  // rank 0 only: every worker was told to stop

enum class ResultKind : std::uint8_t { kTransitions = 0, kStiffness = 1 };

std::string megabytes(long long bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f MB", bytes / 1e6);
  return buf;
}

// Sends stop to the listed workers and serves them until each said bye; results still in
// flight are dropped. Returns the bye messages by rank.
std::map<int, mpi::Message> stop_workers(const std::vector<int>& ranks, mpi::PendingSends& sends) {
  for (int r : ranks) sends.post(r, mpi::kStop, {});
  std::map<int, mpi::Message> byes;
  while (byes.size() < ranks.size()) {
    mpi::Message m = mpi::receive(-1, &sends);
    if (m.tag == mpi::kBye) byes.emplace(m.source, std::move(m));
  }
  sends.wait_all();
  return byes;
}

class MpiEngine final : public TransitionEngine {
 public:
  MpiEngine(const StageContext& ctx, const ProbeModel& probe, const BlobStore& blobs,
            const MpiSession& session, int threads, SolverAlgorithm algorithm)
      : threads_(threads),
        load_source_(blob_source_loader(blobs, rest_displacements(ctx.problem), probe.layout())),
        start_(Clock::now()) {
    for (int r = 1; r < session.size(); ++r)
      workers_.push_back(Worker{r, 0, 0, 0, 0.0, SolverTimings{}, 0});
    wire::Setup setup;
    setup.algorithm = algorithm;
    setup.threads = threads;
    setup.scene_text = ctx.scene_record.text;
    setup.scene_label = ctx.dir.catalogue().string() + " (stored scene, sent by rank 0)";
    setup.problem_hash = ctx.problem_hash.value;
    setup.problem = problem_vectors(ctx.problem);
    wire::Writer w;
    wire::put(w, setup);
    // One buffer for all (it holds the mesh): every worker is waiting for it, so a blocking
    // send returns at once.
    for (const Worker& worker : workers_) mpi::send(worker.rank, mpi::kSetup, w.bytes());
    // How far past the batch being collected workers may run: enough that none waits while
    // the batch's slowest transition finishes and rank 0 stores it, and that each worker gets
    // whole sources (TransitionSolver::lookahead: four per thread, rank 0 holding at most about
    // 1 GiB of results), bounded by the wave.
    lookahead_ = TransitionSolver::lookahead(static_cast<int>(workers_.size()) * threads_,
                                             3 * static_cast<int>(ctx.problem.mesh.num_nodes()));
  }

  ~MpiEngine() override {
    try {
      finish();
    } catch (...) {
    }
  }

  void start_wave(const std::vector<TransitionTask>& tasks) override {
    wave_ = &tasks;
    next_ = horizon_ = 0;
    results_.clear();
    ++wave_number_;
  }

  std::vector<TransitionSolve> solve_range(std::size_t begin, std::size_t end,
                                           std::size_t ahead_end) override {
    horizon_ = std::max({horizon_, end, std::min({wave_->size(), end + lookahead_, ahead_end})});
    for (;;) {
      dispatch();
      bool complete = true;
      for (std::size_t k = begin; k < end && complete; ++k) complete = results_.count(k) > 0;
      if (complete) break;
      require_work_in_flight();
      handle(wait());
    }
    std::vector<TransitionSolve> out;
    out.reserve(end - begin);
    for (std::size_t k = begin; k < end; ++k) {
      auto it = results_.find(k);
      out.push_back(std::move(it->second));
      results_.erase(it);
    }
    return out;
  }

  std::vector<StiffnessResult> stiffnesses(const std::vector<StiffnessTask>& tasks) override {
    stiffness_tasks_ = &tasks;
    stiffness_next_ = 0;
    stiffness_results_.assign(tasks.size(), std::nullopt);
    ++stiffness_call_;
    std::size_t done = 0;
    while (done < tasks.size()) {
      dispatch();
      require_work_in_flight();
      handle(wait());
      done = std::count_if(stiffness_results_.begin(), stiffness_results_.end(),
                           [](const auto& r) { return r.has_value(); });
    }
    stiffness_tasks_ = nullptr;
    std::vector<StiffnessResult> out;
    for (auto& r : stiffness_results_) out.push_back(*r);
    return out;
  }

  SolverTimings timings() const override {
    SolverTimings sum;
    for (const Worker& w : workers_) sum += w.timings;
    return sum;
  }

  std::string parameters() const override {
    return "ranks=" + std::to_string(workers_.size() + 1) + " (1 coordinator + " +
           std::to_string(workers_.size()) + " workers x " + std::to_string(threads_) + " threads)";
  }

  std::string summary() const override {
    const double wall = std::chrono::duration<double>(Clock::now() - start_).count();
    std::string out;
    char buf[300];
    long long solved = 0;
    for (const Worker& w : workers_) solved += w.transitions;
    std::snprintf(buf, sizeof buf,
                  "%zu worker ranks x %d threads over %.1f s; rank 0 (coordinator) waited for "
                  "results %.1f s (%.0f%%), sent %s, received %s (%.1f KB per solved transition), "
                  "peak memory %s",
                  workers_.size(), threads_, wall, waited_s_, wall > 0 ? 100 * waited_s_ / wall : 0,
                  megabytes(sends_.bytes_sent()).c_str(), megabytes(bytes_received_).c_str(),
                  solved ? (sends_.bytes_sent() + bytes_received_) / 1e3 / solved : 0.0,
                  megabytes(peak_rss_bytes()).c_str());
    out += buf;
    for (const Worker& w : workers_) {
      std::snprintf(buf, sizeof buf,
                    "\n  rank %d: %lld transitions solved, %lld stiffnesses, %.1f transitions/s "
                    "while busy; busy %.1f s, idle %.1f s (%.0f%%); peak memory %s",
                    w.rank, w.transitions, w.stiffnesses,
                    w.busy_s > 0 ? w.transitions / w.busy_s : 0.0, w.busy_s,
                    std::max(0.0, wall - w.busy_s),
                    wall > 0 ? 100 * std::max(0.0, wall - w.busy_s) / wall : 0.0,
                    megabytes(w.peak_rss).c_str());
      out += buf;
    }
    return out;
  }

  void finish() override {
    if (finished_) return;
    finished_ = true;
    std::vector<int> ranks;
    for (const Worker& w : workers_) ranks.push_back(w.rank);
    // Stopped once: a second stop would wait for byes from ranks that already ended.
    g_workers_released = true;
    std::map<int, mpi::Message> byes;
    try {
      byes = stop_workers(ranks, sends_);
    } catch (...) {
      mpi::abort_job(kExitFailure);  // workers left waiting for a stop would never end
    }
    for (auto& [rank, bye] : byes) {
      wire::Reader r(bye.bytes.data(), bye.bytes.size());
      Worker& w = workers_[rank - 1];
      w.busy_s = r.pod<double>();
      w.timings = wire::get_timings(r);
      w.peak_rss = r.pod<long long>();
    }
  }

 private:
  struct Worker {
    int rank = 0;
    int outstanding = 0;  // chunks sent, results not yet back
    long long transitions = 0, stiffnesses = 0;
    double busy_s = 0;
    SolverTimings timings;
    long long peak_rss = 0;  // bytes, reported when it stops
  };
  static constexpr int kChunksPerWorker = 2;

  // Gives every worker with a free slot a chunk: stiffness tasks first (a batch waits for
  // them), then the wave's next transitions up to the horizon.
  void dispatch() {
    for (Worker& w : workers_) {
      while (w.outstanding < kChunksPerWorker) {
        if (!send_stiffness_chunk(w) && !send_transition_chunk(w)) return;
        ++w.outstanding;
      }
    }
  }

  bool send_stiffness_chunk(Worker& w) {
    if (!stiffness_tasks_ || stiffness_next_ >= stiffness_tasks_->size()) return false;
    wire::StiffnessChunk chunk;
    while (stiffness_next_ < stiffness_tasks_->size() &&
           chunk.jobs.size() < static_cast<std::size_t>(threads_)) {
      const StiffnessTask& t = (*stiffness_tasks_)[stiffness_next_];
      chunk.jobs.push_back(stiffness_next_++);
      chunk.positions.push_back(t.position);
      chunk.vectors.push_back(*t.vectors);
    }
    wire::Writer writer;
    writer.pod(stiffness_call_);
    wire::put(writer, chunk);
    sends_.post(w.rank, mpi::kStiffness, std::move(writer.bytes()));
    return true;
  }

  bool send_transition_chunk(Worker& w) {
    if (!wave_) return false;
    wire::TransitionChunk chunk;
    std::vector<ConfigId> source_ids;
    // Guided chunks of one source's directions where possible: a worker that solves several
    // directions of a source in a row loads and factorises it once (with one task per chunk,
    // every rank factorised every source: 17 ranks on 16 cores, issue 38); whole sources while
    // much of the window is left, down to one task per thread near its end.
    const std::size_t per_thread = static_cast<std::size_t>(threads_);
    const std::size_t most =
        guided_run(horizon_ - std::min(horizon_, next_), workers_.size(), per_thread);
    while (next_ < horizon_ && chunk.jobs.size() < most) {
      const TransitionTask& t = (*wave_)[next_];
      if (chunk.jobs.size() >= per_thread && !chunk.tasks.empty() &&
          t.source.id != chunk.tasks.back().source.id)
        break;
      if (!t.target) {  // outside the grid: nothing to solve
        results_.emplace(next_++, TransitionSolve{});
        continue;
      }
      auto it = std::find(source_ids.begin(), source_ids.end(), t.source.id);
      if (it == source_ids.end()) {
        source_ids.push_back(t.source.id);
        chunk.sources.push_back(source_vectors(t.source));
        it = source_ids.end() - 1;
      }
      chunk.source_of.push_back(static_cast<int>(it - source_ids.begin()));
      chunk.jobs.push_back(next_++);
      chunk.tasks.push_back(t);
    }
    if (chunk.jobs.empty()) return false;
    wire::Writer writer;
    writer.pod(wave_number_);
    wire::put(writer, chunk);
    sends_.post(w.rank, mpi::kTransitions, std::move(writer.bytes()));
    return true;
  }

  void require_work_in_flight() const {
    for (const Worker& w : workers_)
      if (w.outstanding > 0) return;
    throw std::logic_error("MPI coordinator: results missing but no work in flight");
  }

  // The source's vectors, read once for its directions.
  const ConfigVectors& source_vectors(const Configuration& source) {
    if (!cached_source_ || cached_source_->first != source.id)
      cached_source_.emplace(source.id, load_source_(source));
    return cached_source_->second;
  }

  mpi::Message wait() {
    const auto t0 = Clock::now();
    mpi::Message m = mpi::receive(-1, &sends_);
    waited_s_ += std::chrono::duration<double>(Clock::now() - t0).count();
    bytes_received_ += static_cast<long long>(m.bytes.size());
    return m;
  }

  void handle(const mpi::Message& m) {
    Worker& w = workers_.at(m.source - 1);
    wire::Reader r(m.bytes.data(), m.bytes.size());
    if (m.tag == mpi::kError) {
      const auto kind = r.pod<std::uint8_t>();
      const std::string what = "rank " + std::to_string(m.source) + ": " + r.string();
      if (kind == 1) throw InputError(what);
      if (kind == 2) throw EnvironmentError(what);
      throw std::runtime_error(what);
    }
    if (m.tag != mpi::kResult)
      throw std::runtime_error("rank " + std::to_string(m.source) +
                               " sent an unexpected message (tag " + std::to_string(m.tag) + ")");
    --w.outstanding;
    const auto kind = static_cast<ResultKind>(r.pod<std::uint8_t>());
    const auto generation = r.pod<std::uint64_t>();
    const auto count = r.pod<std::uint64_t>();
    for (std::uint64_t k = 0; k < count; ++k) {
      const auto job = r.pod<std::uint64_t>();
      if (kind == ResultKind::kTransitions) {
        TransitionSolve s = wire::get_transition_solve(r);
        ++w.transitions;
        if (generation == wave_number_) results_.emplace(job, std::move(s));
      } else {
        StiffnessResult s = wire::get_stiffness_result(r);
        ++w.stiffnesses;
        if (generation == stiffness_call_ && job < stiffness_results_.size())
          stiffness_results_[job] = s;
      }
    }
    w.busy_s = r.pod<double>();
    w.timings = wire::get_timings(r);
  }

  int threads_;
  SourceLoader load_source_;
  Clock::time_point start_;
  std::vector<Worker> workers_;
  mpi::PendingSends sends_;
  long long bytes_received_ = 0;
  double waited_s_ = 0;
  bool finished_ = false;

  const std::vector<TransitionTask>* wave_ = nullptr;
  std::uint64_t wave_number_ = 0;
  std::size_t next_ = 0, horizon_ = 0, lookahead_ = 0;
  std::map<std::size_t, TransitionSolve> results_;  // solved, not yet collected
  std::optional<std::pair<ConfigId, ConfigVectors>> cached_source_;

  const std::vector<StiffnessTask>* stiffness_tasks_ = nullptr;
  std::uint64_t stiffness_call_ = 0;
  std::size_t stiffness_next_ = 0;
  std::vector<std::optional<StiffnessResult>> stiffness_results_;
};

}  // namespace

TransitionEngineFactory mpi_engine_factory(const MpiSession& session, int threads,
                                           SolverAlgorithm algorithm) {
  return
      [&session, threads, algorithm](const StageContext& ctx, const ProbeModel& probe,
                                     const BlobStore& blobs) -> std::unique_ptr<TransitionEngine> {
        return std::make_unique<MpiEngine>(ctx, probe, blobs, session, threads, algorithm);
      };
}

void release_mpi_workers(const MpiSession& session) {
  if (!session.distributed() || session.rank() != 0 || g_workers_released) return;
  std::vector<int> ranks;
  for (int r = 1; r < session.size(); ++r) ranks.push_back(r);
  g_workers_released = true;
  try {
    mpi::PendingSends sends;
    stop_workers(ranks, sends);
  } catch (...) {
    mpi::abort_job(kExitFailure);
  }
}

}  // namespace hapstate
