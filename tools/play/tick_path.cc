#include "play/tick_path.h"

#include "util/error.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace hapstate::play {

TickPath::TickPath(ProbePath points, double speed, double rate)
    : points_(std::move(points)), speed_(speed), rate_(rate) {
  if (points_.empty()) throw InputError("the probe path has no points");
  if (!(speed > 0) || !std::isfinite(speed))
    throw InputError("--speed must be a positive number of mesh units per second");
  if (!(rate > 0) || !std::isfinite(rate))
    throw InputError("--rate must be a positive number of Hz");
  arc_.resize(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (!points_[i].allFinite())
      throw InputError("probe path point " + std::to_string(i + 1) + " is not finite");
    arc_[i] = i == 0 ? 0.0 : arc_[i - 1] + (points_[i] - points_[i - 1]).norm();
  }
  const double ticks = std::ceil(duration() * rate_ - 1e-9);
  if (ticks > 1e8)
    throw InputError("the path takes over 1e8 ticks at this speed and rate: raise --speed");
  num_ticks_ = static_cast<std::int64_t>(std::max(0.0, ticks)) + 1;
}

std::array<double, 3> TickPath::Sampler::position(std::int64_t tick) {
  const TickPath& p = path_;
  const double s = std::min(p.length(), static_cast<double>(tick) / p.rate_ * p.speed_);
  while (segment_ + 1 < p.points_.size() && p.arc_[segment_ + 1] < s) ++segment_;
  if (segment_ + 1 >= p.points_.size()) {
    const auto& q = p.points_.back();
    return {q.x(), q.y(), q.z()};
  }
  const double a = p.arc_[segment_], b = p.arc_[segment_ + 1];
  const double w = b > a ? (s - a) / (b - a) : 1.0;
  const Eigen::Vector3d q = (1 - w) * p.points_[segment_] + w * p.points_[segment_ + 1];
  return {q.x(), q.y(), q.z()};
}

}  // namespace hapstate::play
