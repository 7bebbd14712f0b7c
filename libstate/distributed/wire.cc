#include "distributed/wire.h"

#include <cstring>
#include <stdexcept>

namespace hapstate::wire {
namespace {

void put_vec3(Writer& w, const Eigen::Vector3d& v) {
  w.pod(v.x());
  w.pod(v.y());
  w.pod(v.z());
}

Eigen::Vector3d get_vec3(Reader& r) {
  const double x = r.pod<double>(), y = r.pod<double>(), z = r.pod<double>();
  return {x, y, z};
}

}  // namespace

void Writer::append(const void* data, std::size_t size) {
  if (size == 0) return;  // data may be null (an empty vector's)
  const std::size_t at = bytes_.size();
  bytes_.resize(at + size);
  std::memcpy(bytes_.data() + at, data, size);
}

void Writer::string(const std::string& s) {
  pod<std::uint64_t>(s.size());
  append(s.data(), s.size());
}

const char* Reader::take(std::size_t n) {
  if (static_cast<std::size_t>(end_ - p_) < n)
    throw std::runtime_error("MPI message ends early (different builds?)");
  const char* p = p_;
  p_ += n;
  return p;
}

// No count in a message can exceed the elements the bytes left could hold.
std::uint64_t Reader::count(std::uint64_t n, std::size_t size) const {
  if (n > static_cast<std::uint64_t>(end_ - p_) / size)
    throw std::runtime_error("MPI message: count " + std::to_string(n) +
                             " exceeds the message (different builds?)");
  return n;
}

std::string Reader::string() {
  const auto n = count(pod<std::uint64_t>(), 1);
  const char* p = take(n);
  return std::string(p, n);
}

void put(Writer& w, const Setup& s) {
  w.pod(static_cast<int>(s.algorithm));
  w.pod(s.threads);
  w.string(s.scene_text);
  w.string(s.scene_label);
  w.pod(s.problem_hash);
  const ProblemVectors& p = s.problem;
  for (const auto* v : {&p.nodes, &p.tets, &p.surface, &p.role, &p.probe_nodes, &p.probe_components,
                        &p.rest, &p.force, &p.spring, &p.rest_u, &p.sag})
    w.values(*v);
}

Setup get_setup(Reader& r) {
  Setup s;
  s.algorithm = static_cast<SolverAlgorithm>(r.pod<int>());
  s.threads = r.pod<int>();
  s.scene_text = r.string();
  s.scene_label = r.string();
  s.problem_hash = r.pod<std::uint64_t>();
  ProblemVectors& p = s.problem;
  for (auto* v : {&p.nodes, &p.tets, &p.surface, &p.role, &p.probe_nodes, &p.probe_components,
                  &p.rest, &p.force, &p.spring, &p.rest_u, &p.sag})
    *v = r.values<double>();
  return s;
}

void put(Writer& w, const ConfigVectors& v) {
  w.values(v.u);
  w.values(v.t);
  w.values(v.h);
  w.values(v.touched);
  w.values(v.multipliers);
}

ConfigVectors get_vectors(Reader& r) {
  ConfigVectors v;
  v.u = r.values<double>();
  v.t = r.values<double>();
  v.h = r.values<double>();
  v.touched = r.values<int>();
  v.multipliers = r.values<double>();
  return v;
}

void put(Writer& w, const TransitionChunk& c) {
  w.pod<std::uint64_t>(c.sources.size());
  for (const ConfigVectors& v : c.sources) put(w, v);
  w.pod<std::uint64_t>(c.tasks.size());
  for (std::size_t k = 0; k < c.tasks.size(); ++k) {
    const TransitionTask& t = c.tasks[k];
    w.pod(c.jobs[k]);
    w.pod(c.source_of[k]);
    w.pod(t.source.id.value());
    w.pod<std::uint8_t>(t.source.blob ? 1 : 0);
    w.pod(t.source.blob ? t.source.blob->segment.value : SegmentId{}.value);
    w.string(t.source.blob ? t.source.blob->name : std::string());
    w.pod(t.direction.index());
    put_vec3(w, t.from);
    put_vec3(w, t.to);
    w.pod<std::uint8_t>(t.target ? 1 : 0);
    w.pod(t.target ? t.target->value() : std::int64_t{0});
  }
}

TransitionChunk get_transition_chunk(Reader& r) {
  TransitionChunk c;
  const auto sources = r.pod<std::uint64_t>();
  for (std::uint64_t k = 0; k < sources; ++k) c.sources.push_back(get_vectors(r));
  const auto tasks = r.pod<std::uint64_t>();
  for (std::uint64_t k = 0; k < tasks; ++k) {
    TransitionTask t;
    c.jobs.push_back(r.pod<std::uint64_t>());
    const int source = r.pod<int>();
    if (source < 0 || static_cast<std::size_t>(source) >= c.sources.size())
      throw std::runtime_error("MPI message: source index out of range (different builds?)");
    c.source_of.push_back(source);
    t.source.id = ConfigId(r.pod<std::int64_t>());
    // The source's blob reference as stored (the worker never reads it: the vectors travel in
    // the chunk; a source without one is a zero state).
    const bool has_blob = r.pod<std::uint8_t>() != 0;
    const auto segment = r.pod<std::int64_t>();
    std::string name = r.string();
    if (has_blob) t.source.blob = BlobRef{SegmentId{segment}, std::move(name)};
    t.direction = Direction(r.pod<int>());
    t.from = get_vec3(r);
    t.to = get_vec3(r);
    const bool has_target = r.pod<std::uint8_t>() != 0;
    const auto target = r.pod<std::int64_t>();
    if (has_target) t.target = CheckpointId(target);
    c.tasks.push_back(std::move(t));
  }
  return c;
}

void put(Writer& w, const StiffnessChunk& c) {
  w.pod<std::uint64_t>(c.jobs.size());
  for (std::size_t k = 0; k < c.jobs.size(); ++k) {
    w.pod(c.jobs[k]);
    put_vec3(w, c.positions[k]);
    put(w, c.vectors[k]);
  }
}

StiffnessChunk get_stiffness_chunk(Reader& r) {
  StiffnessChunk c;
  const auto n = r.pod<std::uint64_t>();
  for (std::uint64_t k = 0; k < n; ++k) {
    c.jobs.push_back(r.pod<std::uint64_t>());
    c.positions.push_back(get_vec3(r));
    c.vectors.push_back(get_vectors(r));
  }
  return c;
}

void put(Writer& w, const TransitionSolve& s) {
  w.pod<std::uint8_t>(s.solved);
  w.pod<std::uint8_t>(s.trivial);
  const MoveResult& m = s.move;
  w.pod<std::uint8_t>(m.ok);
  w.pod(static_cast<int>(m.failure));
  w.string(m.reason);
  for (int v : {m.substeps, m.cutbacks, m.iterations, m.factorisations, m.start_factorisations,
                m.active_set_iterations})
    w.pod(v);
  w.pod(m.residual);
  w.pod(m.wall_ms);
  w.values(m.residual_history);
  put(w, s.vectors);
  for (double f : s.force) w.pod(f);
  w.pod<std::uint8_t>(s.midpoint_force.has_value());
  if (s.midpoint_force)
    for (double f : *s.midpoint_force) w.pod(f);
  w.pod<std::uint8_t>(s.midpoint_stiffness.has_value());
  if (s.midpoint_stiffness)
    for (double k : *s.midpoint_stiffness) w.pod(k);
  w.values(s.midpoint_u);
  w.values(s.midpoint_du_dp);
}

TransitionSolve get_transition_solve(Reader& r) {
  TransitionSolve s;
  s.solved = r.pod<std::uint8_t>() != 0;
  s.trivial = r.pod<std::uint8_t>() != 0;
  MoveResult& m = s.move;
  m.ok = r.pod<std::uint8_t>() != 0;
  m.failure = static_cast<SolveFailure>(r.pod<int>());
  m.reason = r.string();
  for (int* v : {&m.substeps, &m.cutbacks, &m.iterations, &m.factorisations,
                 &m.start_factorisations, &m.active_set_iterations})
    *v = r.pod<int>();
  m.residual = r.pod<double>();
  m.wall_ms = r.pod<double>();
  m.residual_history = r.values<double>();
  s.vectors = get_vectors(r);
  for (double& f : s.force) f = r.pod<double>();
  if (r.pod<std::uint8_t>() != 0) {
    std::array<double, 3> m{};
    for (double& f : m) f = r.pod<double>();
    s.midpoint_force = m;
  }
  if (r.pod<std::uint8_t>() != 0) {
    std::array<double, 9> k{};
    for (double& v : k) v = r.pod<double>();
    s.midpoint_stiffness = k;
  }
  s.midpoint_u = r.values<float>();
  s.midpoint_du_dp = r.values<float>();
  return s;
}

void put(Writer& w, const StiffnessResult& s) {
  for (double k : s.stiffness) w.pod(k);
  w.values(s.du_dp);
  w.pod(s.factorisations);
}

StiffnessResult get_stiffness_result(Reader& r) {
  StiffnessResult s;
  for (double& k : s.stiffness) k = r.pod<double>();
  s.du_dp = r.values<float>();
  s.factorisations = r.pod<int>();
  return s;
}

void put(Writer& w, const SolverTimings& t) {
  for (double v : {t.assembly, t.factorize, t.solve, t.analyze, t.contact_detection, t.factor_bytes,
                   t.single_factor_bytes})
    w.pod(v);
  for (long long v : {t.assemblies, t.factorisations, t.psd_fallbacks, t.inner_iterations,
                      t.contact_queries, t.back_substitutions, t.single_back_substitutions})
    w.pod(v);
}

SolverTimings get_timings(Reader& r) {
  SolverTimings t;
  for (double* v : {&t.assembly, &t.factorize, &t.solve, &t.analyze, &t.contact_detection,
                    &t.factor_bytes, &t.single_factor_bytes})
    *v = r.pod<double>();
  for (long long* v : {&t.assemblies, &t.factorisations, &t.psd_fallbacks, &t.inner_iterations,
                       &t.contact_queries, &t.back_substitutions, &t.single_back_substitutions})
    *v = r.pod<long long>();
  return t;
}

}  // namespace hapstate::wire
