#include "eval/region_path.h"

#include "util/error.h"
#include "util/grid_direction.h"

#include <cmath>

namespace hapstate {
namespace {

// Whether configuration c was expanded: some transition decided (a partial expansion leaves
// its frontier open, a configuration past F_max is never expanded).
bool expanded(const PlaybackFile& file, std::int32_t c) {
  for (int d = 0; d < grid::kDirections; ++d)
    if (file.transition_entry(c, d) != -1) return true;  // -1: undecided
  return false;
}

// Whether every corner of the cursor's cell is stored and expanded, so that the corners of the
// next cells come from the transitions of the side the cursor came from. Along an axis with a
// single check-point the cell is flat and only its first corners count.
bool corners_stored(const PlaybackFile& file, const HapticCursor& cursor) {
  const auto dims = file.grid_dims();
  for (int c = 0; c < 8; ++c) {
    if ((dims[0] == 1 && (c & 4)) || (dims[1] == 1 && (c & 2)) || (dims[2] == 1 && (c & 1)))
      continue;
    if (cursor.corner_source(c) != CornerSource::kStored ||
        !expanded(file, cursor.corner_configuration(c)))
      return false;
  }
  return true;
}

class RegionWalker {
 public:
  explicit RegionWalker(const PlaybackFile& file) : file_(file), cursor_(file, Scheme::kTrilinear) {
    const auto h = file.grid_spacing();
    sample_ = 0.1 * std::min({h[0], h[1], h[2]});
  }
  // Moves the cursor from a to b in samples of a tenth of the smallest spacing; false as soon
  // as the probe leaves the grid or a corner is not stored (the cursor is then somewhere on
  // the segment).
  bool move(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const int samples = 1 + static_cast<int>(std::ceil((b - a).norm() / sample_));
    for (int s = 1; s <= samples; ++s) {
      const Eigen::Vector3d q = a + (b - a) * (static_cast<double>(s) / samples);
      if (!cursor_.force({q.x(), q.y(), q.z()}).inside_grid) return false;
      if (!corners_stored(file_, cursor_)) return false;
    }
    return true;
  }
  // Puts the cursor back where it was after following `path` from `start`.
  void replay(const Eigen::Vector3d& start, const ProbePath& path) {
    cursor_.reset();
    Eigen::Vector3d p = start;
    cursor_.force({p.x(), p.y(), p.z()});
    for (const Eigen::Vector3d& q : path) {
      move(p, q);
      p = q;
    }
  }
  bool stored_here() const { return corners_stored(file_, cursor_); }

 private:
  const PlaybackFile& file_;
  HapticCursor cursor_;
  double sample_;
};

// Unit vector from p to the nearest view node's reference position (zero if there is none).
Eigen::Vector3d toward_body(const PlaybackFile& file, const Eigen::Vector3d& p) {
  const auto ref = file.reference_positions();
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double best_d2 = INFINITY;
  for (std::size_t v = 0; v + 3 <= ref.size(); v += 3) {
    const Eigen::Vector3d d(ref[v] - p.x(), ref[v + 1] - p.y(), ref[v + 2] - p.z());
    if (d.squaredNorm() < best_d2) best_d2 = d.squaredNorm(), best = d;
  }
  return best.norm() > 0 ? Eigen::Vector3d(best.normalized()) : best;
}

}  // namespace

ProbePath precomputed_random_path(const PlaybackFile& file, int steps, double step_length,
                                  std::uint64_t seed, double pull) {
  const auto rest = file.rest_position();
  const Eigen::Vector3d start(rest[0], rest[1], rest[2]);
  RegionWalker walker(file);
  walker.replay(start, {});
  if (!walker.stored_here())
    throw InputError(file.path().string() +
                     ": the cell around the rest position is not precomputed "
                     "(some corner has no configuration): run hapstate-expand further");
  RandomDirections rng(seed);
  const auto dims = file.grid_dims();
  ProbePath path;
  Eigen::Vector3d p = start;
  for (int s = 0; s < steps; ++s) {
    double length = step_length;
    bool moved = false;
    while (!moved && length > 1e-6 * step_length) {
      for (int attempt = 0; attempt < 200 && !moved; ++attempt) {
        Eigen::Vector3d direction = rng.direction();
        if (file.is_contact()) direction += pull * toward_body(file, p);
        for (int a = 0; a < 3; ++a)
          if (dims[a] == 1) direction[a] = 0.0;
        if (direction.norm() < 1e-3) continue;
        const Eigen::Vector3d next = p + length * direction.normalized();
        if (walker.move(p, next)) {
          p = next;
          moved = true;
        } else {
          walker.replay(start, path);
        }
      }
      length *= 0.5;
    }
    path.push_back(p);
  }
  return path;
}

}  // namespace hapstate
