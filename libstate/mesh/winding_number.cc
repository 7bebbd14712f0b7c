#include "mesh/winding_number.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace hapstate {

WindingNumber::WindingNumber(const TriangleSurface& s) {
  corners_.reserve(9 * s.faces.size());
  for (const auto& f : s.faces) {
    for (int v : f) {
      for (int k = 0; k < 3; ++k)
        corners_.push_back(s.xyz[3 * static_cast<std::size_t>(v) + static_cast<std::size_t>(k)]);
    }
    add_volume();
  }
}

WindingNumber::WindingNumber(const Eigen::Matrix3Xd& xyz, const Triangles& faces) {
  corners_.reserve(9 * static_cast<std::size_t>(faces.cols()));
  for (Eigen::Index t = 0; t < faces.cols(); ++t) {
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) corners_.push_back(xyz(k, faces(i, t)));
    add_volume();
  }
}

void WindingNumber::add_volume() {
  const double* c = corners_.data() + corners_.size() - 9;
  const Eigen::Vector3d a(c[0], c[1], c[2]);
  const Eigen::Vector3d b(c[3], c[4], c[5]);
  const Eigen::Vector3d d(c[6], c[7], c[8]);
  volume_ += a.dot(b.cross(d)) / 6.0;
}

double WindingNumber::operator()(const Eigen::Vector3d& p) const {
  // Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom & Strackee 1983):
  // tan(omega / 2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|).
  double sum = 0;
  const double* c = corners_.data();
  const double* end = c + corners_.size();
  for (; c != end; c += 9) {
    const double ax = c[0] - p.x(), ay = c[1] - p.y(), az = c[2] - p.z();
    const double bx = c[3] - p.x(), by = c[4] - p.y(), bz = c[5] - p.z();
    const double cx = c[6] - p.x(), cy = c[7] - p.y(), cz = c[8] - p.z();
    const double la = std::sqrt(ax * ax + ay * ay + az * az);
    const double lb = std::sqrt(bx * bx + by * by + bz * bz);
    const double lc = std::sqrt(cx * cx + cy * cy + cz * cz);
    const double det =
        ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    const double ab = ax * bx + ay * by + az * bz;
    const double bc = bx * cx + by * cy + bz * cz;
    const double ca = cx * ax + cy * ay + cz * az;
    sum += std::atan2(det, la * lb * lc + ab * lc + bc * la + ca * lb);
  }
  return sum * 2.0 / (4.0 * std::numbers::pi);
}

}  // namespace hapstate
