// A probe path as a device would play it: the path's points visited in order at a constant
// speed (mesh units per second), linear between points, sampled at a fixed tick rate.
#pragma once

#include "io/probe_path.h"

#include <array>
#include <cstdint>
#include <vector>

namespace hapstate::play {

class TickPath {
 public:
  // `points` not empty, `speed` and `rate` (Hz) > 0. Throws InputError otherwise.
  TickPath(ProbePath points, double speed, double rate);

  std::int64_t num_ticks() const { return num_ticks_; }  // tick 0 at the first point
  double rate() const { return rate_; }
  double length() const { return arc_.back(); }             // mesh units
  double duration() const { return arc_.back() / speed_; }  // seconds
  std::size_t num_points() const { return points_.size(); }

  // Sequential sampling without allocation: position of tick 0, 1, 2, ... in turn.
  class Sampler {
   public:
    explicit Sampler(const TickPath& path) : path_(path) {}
    std::array<double, 3> position(std::int64_t tick);  // ticks in increasing order
   private:
    const TickPath& path_;
    std::size_t segment_ = 0;
  };

 private:
  ProbePath points_;
  std::vector<double> arc_;  // arc length at each point
  double speed_;
  double rate_;
  std::int64_t num_ticks_;
};

}  // namespace hapstate::play
