#include "playback/cell_bubbles.h"

namespace hapstate::playback {
namespace {

// Corner index from its sides per axis (bits x y z, as HapticCursor's corners).
int corner(int ox, int oy, int oz) { return (ox << 2) | (oy << 1) | oz; }

// Along a bubble's own axes: 16 t^2 (1 - t)^2, 1 at the middle, 0 with zero slope at the ends.
double middle(double t) { return 16.0 * t * t * (1.0 - t) * (1.0 - t); }
double middle_slope(double t) { return 32.0 * t * (1.0 - t) * (1.0 - 2.0 * t); }
// Across them: the cubic Hermite value basis of side o (1 on that side, 0 on the other, zero
// slope at both).
double side(int o, double t) {
  const double h1 = t * t * (3.0 - 2.0 * t);
  return o ? h1 : 1.0 - h1;
}
double side_slope(int o, double t) {
  const double d = 6.0 * t * (1.0 - t);
  return o ? d : -d;
}

}  // namespace

BubbleSpec bubble_spec(int k) {
  BubbleSpec b{};
  if (k < kEdgeBubbles) {
    const int a = k / 4, o1 = (k / 2) % 2, o2 = k % 2;
    int o[3];
    o[a] = 0;
    o[(a + 1) % 3] = o1;
    o[(a + 2) % 3] = o2;
    b.kind = BubbleKind::kEdge;
    b.source_corner = corner(o[0], o[1], o[2]);
    b.target_corner = b.source_corner | (4 >> a);
    b.direction = a;  // kMidpointOffsets: +x, +y, +z first
    b.point = {double(o[0]), double(o[1]), double(o[2])};
    b.point[a] = 0.5;
    return b;
  }
  if (k < kEdgeBubbles + kFaceBubbles) {
    const int a = (k - kEdgeBubbles) / 2, o = (k - kEdgeBubbles) % 2;
    const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
    b.kind = BubbleKind::kFace;
    b.source_corner = o ? (4 >> a) : 0;
    b.target_corner = b.source_corner | (4 >> b1) | (4 >> b2);
    b.direction = 5 - a;  // face normal to x: (0, 1, 1) = 5; y: (1, 0, 1) = 4; z: (1, 1, 0) = 3
    b.point = {0.5, 0.5, 0.5};
    b.point[a] = o;
    return b;
  }
  b.kind = BubbleKind::kCell;
  b.source_corner = 0;
  b.target_corner = 7;
  b.direction = 6;
  b.point = {0.5, 0.5, 0.5};
  return b;
}

double bubble_weight(int k, const std::array<double, 3>& s, std::array<double, 3>* gradient) {
  // Per axis: the factor and its slope.
  double f[3], d[3];
  if (k < kEdgeBubbles) {
    const int a = k / 4, o1 = (k / 2) % 2, o2 = k % 2;
    const int b1 = (a + 1) % 3, b2 = (a + 2) % 3;
    f[a] = middle(s[a]), d[a] = middle_slope(s[a]);
    f[b1] = side(o1, s[b1]), d[b1] = side_slope(o1, s[b1]);
    f[b2] = side(o2, s[b2]), d[b2] = side_slope(o2, s[b2]);
  } else if (k < kEdgeBubbles + kFaceBubbles) {
    const int a = (k - kEdgeBubbles) / 2, o = (k - kEdgeBubbles) % 2;
    for (int x = 0; x < 3; ++x) f[x] = middle(s[x]), d[x] = middle_slope(s[x]);
    f[a] = side(o, s[a]), d[a] = side_slope(o, s[a]);
  } else {
    for (int x = 0; x < 3; ++x) f[x] = middle(s[x]), d[x] = middle_slope(s[x]);
  }
  if (gradient) *gradient = {d[0] * f[1] * f[2], f[0] * d[1] * f[2], f[0] * f[1] * d[2]};
  return f[0] * f[1] * f[2];
}

namespace {

// The weights of every bubble at every bubble's point, computed once at compile time from the
// positions in half cells (0, 1, 2).
struct PointWeights {
  double w[kCellBubbles][kCellBubbles];
};
constexpr double middle_at(int half) { return half == 1 ? 1.0 : 0.0; }
constexpr double side_at(int o, int half) {
  const double v1 = half == 0 ? 0.0 : (half == 1 ? 0.5 : 1.0);
  return o ? v1 : 1.0 - v1;
}
constexpr PointWeights point_weights() {
  PointWeights t{};
  for (int j = 0; j < kCellBubbles; ++j) {
    int p[3];  // bubble j's point in half cells
    if (j < kEdgeBubbles) {
      const int a = j / 4;
      p[a] = 1;
      p[(a + 1) % 3] = 2 * ((j / 2) % 2);
      p[(a + 2) % 3] = 2 * (j % 2);
    } else if (j < kEdgeBubbles + kFaceBubbles) {
      const int a = (j - kEdgeBubbles) / 2;
      p[0] = p[1] = p[2] = 1;
      p[a] = 2 * ((j - kEdgeBubbles) % 2);
    } else {
      p[0] = p[1] = p[2] = 1;
    }
    for (int k = 0; k < kCellBubbles; ++k) {
      double f[3];
      if (k < kEdgeBubbles) {
        const int a = k / 4;
        f[a] = middle_at(p[a]);
        f[(a + 1) % 3] = side_at((k / 2) % 2, p[(a + 1) % 3]);
        f[(a + 2) % 3] = side_at(k % 2, p[(a + 2) % 3]);
      } else {
        for (int x = 0; x < 3; ++x) f[x] = middle_at(p[x]);
        if (k < kEdgeBubbles + kFaceBubbles) {
          const int a = (k - kEdgeBubbles) / 2;
          f[a] = side_at((k - kEdgeBubbles) % 2, p[a]);
        }
      }
      t.w[k][j] = f[0] * f[1] * f[2];
    }
  }
  return t;
}
constexpr PointWeights kPointWeights = point_weights();

}  // namespace

double bubble_weight_at_point(int k, int j) { return kPointWeights.w[k][j]; }

}  // namespace hapstate::playback
