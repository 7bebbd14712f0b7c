// The byte encoding of what the expand stage's coordinator and worker ranks exchange
// (distributed/mpi_engine.h): the set-up (stored scene text and problem vectors), chunks of
// transition or stiffness tasks with their source vectors, and their results. Plain
// little-endian copies of the in-memory values (the ranks run the same build), so a worker
// solves exactly what a thread in the coordinator's process would. No MPI here: the encoding is
// tested on its own.
#pragma once

#include "solver/path_solver.h"
#include "statedir/stored_problem.h"
#include "statespace/expand_batch.h"

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace hapstate::wire {

// Appends values to a byte buffer.
class Writer {
 public:
  template <typename T>
  void pod(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    append(&value, sizeof(T));
  }
  void append(const void* data, std::size_t size);
  void string(const std::string& s);
  // A count, then the values (doubles, floats, ints).
  template <typename T>
  void values(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod<std::uint64_t>(v.size());
    append(v.data(), v.size() * sizeof(T));
  }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

// Reads them back in the same order; throws std::runtime_error (an internal error: the peer is
// the same program) when the buffer ends early or a count is absurd.
class Reader {
 public:
  Reader(const char* data, std::size_t size) : p_(data), end_(data + size) {}
  template <typename T>
  T pod() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
    return value;
  }
  std::string string();
  template <typename T>
  std::vector<T> values() {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::uint64_t n = count(pod<std::uint64_t>(), sizeof(T));
    std::vector<T> v(n);
    const char* p = take(n * sizeof(T));
    if (n) std::memcpy(v.data(), p, n * sizeof(T));  // (memcpy of null, even 0 bytes, is UB)
    return v;
  }
  bool done() const { return p_ == end_; }

 private:
  const char* take(std::size_t n);
  // A count of elements of `size` bytes read from the buffer, checked against what is left.
  std::uint64_t count(std::uint64_t n, std::size_t size) const;
  const char* p_;
  const char* end_;
};

// What a worker needs to build its solvers.
struct Setup {
  SolverAlgorithm algorithm = SolverAlgorithm::kFast;
  int threads = 1;
  std::string scene_text;   // the catalogue's stored scene
  std::string scene_label;  // names it in messages
  std::uint64_t problem_hash = 0;
  ProblemVectors problem;
};
void put(Writer& w, const Setup& s);
Setup get_setup(Reader& r);

// A chunk of transition tasks: each task's source configuration travels once per chunk with
// its vectors. `jobs` are the coordinator's indices of the tasks (echoed in the results).
struct TransitionChunk {
  std::vector<std::uint64_t> jobs;
  std::vector<TransitionTask> tasks;
  std::vector<ConfigVectors> sources;  // sources[source_of[k]] belongs to tasks[k]
  std::vector<int> source_of;
};
void put(Writer& w, const TransitionChunk& c);
TransitionChunk get_transition_chunk(Reader& r);

struct StiffnessChunk {
  std::vector<std::uint64_t> jobs;
  std::vector<Eigen::Vector3d> positions;
  std::vector<ConfigVectors> vectors;
};
void put(Writer& w, const StiffnessChunk& c);
StiffnessChunk get_stiffness_chunk(Reader& r);

void put(Writer& w, const ConfigVectors& v);
ConfigVectors get_vectors(Reader& r);
void put(Writer& w, const TransitionSolve& s);
TransitionSolve get_transition_solve(Reader& r);
void put(Writer& w, const StiffnessResult& s);
StiffnessResult get_stiffness_result(Reader& r);
void put(Writer& w, const SolverTimings& t);
SolverTimings get_timings(Reader& r);

}  // namespace hapstate::wire
