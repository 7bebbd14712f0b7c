#include "util/triangle_point.h"

namespace hapstate {
namespace {

TrianglePoint at_weights(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c, const Eigen::Vector3d& q, double wa, double wb,
                         double wc) {
  TrianglePoint tp;
  tp.weights = {wa, wb, wc};
  tp.closest = wa * a + wb * b + wc * c;
  tp.distance = (q - tp.closest).norm();
  return tp;
}

}  // namespace

// Classifies q against the Voronoi regions of the corners, edges and face of the triangle with
// dot products of the edge vectors only (no normal is needed, so needles work).
TrianglePoint closest_point(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c, const Eigen::Vector3d& q) {
  const Eigen::Vector3d ab = b - a, ac = c - a, aq = q - a;
  const double d1 = ab.dot(aq), d2 = ac.dot(aq);
  if (d1 <= 0 && d2 <= 0) return at_weights(a, b, c, q, 1, 0, 0);
  const Eigen::Vector3d bq = q - b;
  const double d3 = ab.dot(bq), d4 = ac.dot(bq);
  if (d3 >= 0 && d4 <= d3) return at_weights(a, b, c, q, 0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return at_weights(a, b, c, q, 1 - v, v, 0);
  }
  const Eigen::Vector3d cq = q - c;
  const double d5 = ab.dot(cq), d6 = ac.dot(cq);
  if (d6 >= 0 && d5 <= d6) return at_weights(a, b, c, q, 0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return at_weights(a, b, c, q, 1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at_weights(a, b, c, q, 0, 1 - w, w);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return at_weights(a, b, c, q, 1 - v - w, v, w);
}

}  // namespace hapstate
