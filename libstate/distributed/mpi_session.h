// MPI for the expand stage: initialised only when the process was started by an MPI launcher
// (mpirun / mpiexec / srun set OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_SIZE), so the same
// executable still runs alone without touching MPI. Rank 0 coordinates; the others are workers
// (distributed/mpi_engine.h). Only the main thread of each rank calls MPI.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace hapstate {

// True when an MPI launcher started this process.
bool launched_by_mpi();

// This process's peak resident memory so far, bytes (each rank reports its own).
long long peak_rss_bytes();

class MpiSession {
 public:
  // Calls MPI_Init_thread (FUNNELED) if launched_by_mpi(); otherwise does nothing. Under MPI the
  // process also asks Linux to kill it when its launcher dies (mpirun killed with SIGKILL must not
  // leave ranks running that hold the state directory).
  MpiSession(int* argc, char*** argv);
  ~MpiSession();  // MPI_Finalize
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  bool initialised() const { return initialised_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  // More than one rank: rank 0 coordinates, the others work.
  bool distributed() const { return size_ > 1; }

 private:
  bool initialised_ = false;
  int rank_ = 0;
  int size_ = 1;
};

// Point-to-point byte messages on MPI_COMM_WORLD.
namespace mpi {

enum Tag : int {
  kSetup = 1,        // coordinator -> worker: wire::Setup
  kTransitions = 2,  // coordinator -> worker: a wire::TransitionChunk
  kStiffness = 3,    // coordinator -> worker: a wire::StiffnessChunk
  kStop = 4,         // coordinator -> worker: no more work (answered by kBye)
  kResult = 5,       // worker -> coordinator: results of one chunk
  kError = 6,        // worker -> coordinator: an exception while working on a chunk
  kBye = 7,          // worker -> coordinator: final statistics; the worker then ends
};

struct Message {
  int source = 0;
  int tag = 0;
  std::vector<char> bytes;
};

// The next message from `source` (any rank if negative), if one has arrived.
std::optional<Message> try_receive(int source);
class PendingSends;
// Waits for the next message from `source` (any rank if negative), completing `sends` (if
// given) meanwhile. Polls with short sleeps (20 us growing to 1 ms) instead of spinning, so a
// waiting rank leaves its core to the others (ranks are often oversubscribed: a coordinator
// beside workers on the same cores).
Message receive(int source, PendingSends* sends = nullptr);
// Sends and returns once the buffer may be reused (the peer may not have received it yet).
void send(int dest, int tag, const std::vector<char>& bytes);
// Ends every rank of the job (MPI_Abort) with `code`: for a rank that cannot go on with the
// protocol (the others would wait for it forever).
[[noreturn]] void abort_job(int code);

// Sends that must not block the coordinator while the receiving worker is busy solving (a
// large message waits for the receiver under MPI's rendezvous protocol): post() keeps the
// buffer until the send completed; progress() frees completed ones.
class PendingSends {
 public:
  PendingSends();
  ~PendingSends();
  void post(int dest, int tag, std::vector<char> bytes);
  void progress();
  void wait_all();
  long long bytes_sent() const { return bytes_sent_; }

 private:
  struct Pending;
  std::vector<std::unique_ptr<Pending>> pending_;
  long long bytes_sent_ = 0;
};

}  // namespace mpi
}  // namespace hapstate
