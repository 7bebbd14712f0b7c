// Values between the check-points (docs/playback.md, "Between the check-points"): the force
// recorded half-way through the moves in the 7 directions of playback::kMidpointOffsets is the
// force at an edge midpoint, a face centre or a cell centre of the grid. A cell adds to its
// interpolant one bubble per edge, face and cell whose value is known there, fitted in that order
// so that the interpolant passes through those values. Every bubble is zero at every corner;
// the Hermite scheme's (bubble_weight: 16 t^2 (1 - t)^2 along its axes) also with zero slope, so
// check-points and their stiffness stay exact. The trilinear scheme's hats (1 - |2 t - 1|) take
// the same values at the 27 points, so one fit serves both. The bubbles of an edge or face
// depend only on that edge's or face's data (the force stays continuous across faces).
#pragma once

#include <array>

namespace hapstate::playback {

// 12 edges (k = 4 a + 2 o1 + o2: along axis a, on side o1 of axis (a + 1) % 3 and side o2 of
// axis (a + 2) % 3), 6 faces (k = 12 + 2 a + o: normal to axis a, on side o), the cell (k = 18).
inline constexpr int kCellBubbles = 19;
inline constexpr int kEdgeBubbles = 12;
inline constexpr int kFaceBubbles = 6;

enum class BubbleKind { kEdge = 0, kFace = 1, kCell = 2 };

struct BubbleSpec {
  BubbleKind kind;
  int source_corner;  // the corner (bits x y z, as the cursor's) whose move records the value
  int target_corner;  // the corner that move ends at
  int direction;      // index into kMidpointOffsets
  std::array<double, 3> point;  // the cell position where the value holds
};
BubbleSpec bubble_spec(int k);

// Bubble k's weight at cell position s (each in [0, 1]) and its gradient with respect to s.
double bubble_weight(int k, const std::array<double, 3>& s, std::array<double, 3>* gradient);

// Bubble k's weight at bubble j's point: 0, 1/4, 1/2 or 1 (the factors there are 16 t^2 (1-t)^2
// in {0, 1} and value bases in {0, 1/2, 1}).
double bubble_weight_at_point(int k, int j);

// The corrections of a cell's 19 bubbles, fitted edges first, then faces, then the cell:
// correction k = value(k) minus the interpolant with the bubbles fitted before it, at bubble k's
// point; 0 where `value` gives none. `interpolant(s, out)` writes the cell's interpolant without
// bubbles at s; `value(k, out)` writes bubble k's recorded force and returns true, or returns
// false. Each component is clamped to +-limit[kind] (so that the change bound holds whatever
// the corners: docs/playback.md).
template <class Interpolant, class Value>
void fit_bubbles(Interpolant&& interpolant, Value&& value, const double (&limit)[3],
                 std::array<std::array<double, 3>, kCellBubbles>* correction) {
  for (int k = 0; k < kCellBubbles; ++k) {
    (*correction)[k] = {};
    double known[3];
    if (!value(k, known)) continue;
    const BubbleSpec spec = bubble_spec(k);
    double current[3];
    interpolant(spec.point, current);
    for (int j = 0; j < k; ++j) {
      if ((*correction)[j][0] == 0 && (*correction)[j][1] == 0 && (*correction)[j][2] == 0)
        continue;
      const double w = bubble_weight_at_point(j, k);
      for (int r = 0; r < 3; ++r) current[r] += w * (*correction)[j][r];
    }
    const double bound = limit[static_cast<int>(spec.kind)];
    for (int r = 0; r < 3; ++r) {
      const double c = known[r] - current[r];
      (*correction)[k][r] = c > bound ? bound : (c < -bound ? -bound : c);
    }
  }
}

}  // namespace hapstate::playback
