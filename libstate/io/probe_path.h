// Probe paths: absolute probe positions in scene (mesh) units, one per path point.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace hapstate {

using ProbePath = std::vector<Eigen::Vector3d>;

// Reads a CSV with header `x,y,z` (extra columns after these are ignored; blank lines and
// lines starting with '#' skipped). Throws InputError naming file:line on a malformed row.
ProbePath read_probe_path(const std::filesystem::path& file);

// Writes `x,y,z` CSV with full precision.
void write_probe_path(const ProbePath& path, const std::filesystem::path& file);

// `steps` evenly spaced points from `from` (exclusive) to `to` (inclusive).
ProbePath straight_path(const Eigen::Vector3d& from, const Eigen::Vector3d& to, int steps);

// Seeded uniformly distributed unit directions, the same sequence on every platform (splitmix64;
// std distributions differ between standard libraries).
class RandomDirections {
 public:
  explicit RandomDirections(std::uint64_t seed) : state_(seed) {}
  Eigen::Vector3d direction();
  double uniform();  // [0, 1)

 private:
  std::uint64_t next();
  std::uint64_t state_;
};

// Seeded random walk of `steps` points starting next to `start`: each step moves by
// `step_length` in a uniformly random direction; a step that would leave `box` (min, max
// corners) is reflected back inside. Deterministic for a given seed on every platform.
ProbePath random_path(const Eigen::Vector3d& start, int steps, double step_length,
                      const Eigen::Vector3d& box_min, const Eigen::Vector3d& box_max,
                      std::uint64_t seed);

}  // namespace hapstate
