// What the refined-lattice cursor tests share (cursor_eighth_test, cursor_sixteenth_test): the
// synthetic field on a grid of spacing h, files written to a temporary directory, a position in
// cell units, and conversions between the cursor's arrays and Eigen.
#pragma once

#include "hapstate/playback.h"
#include "synthetic.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace hapstate::test_util {

inline Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
inline Eigen::Matrix3d mat(const std::array<double, 9>& a) {
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = a[3 * r + c];
  return m;
}
inline std::array<double, 3> arr(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

// The largest difference between the cursor's stiffness and central differences (step 1e-6) of
// its force at `points`, over the largest stiffness column there: the stiffness is the force's
// derivative where it is small.
inline double stiffness_mismatch(HapticCursor& cursor, const std::vector<Eigen::Vector3d>& points) {
  double worst = 0, scale = 0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Matrix3d k = mat(cursor.force(arr(p)).stiffness);
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[a] = 1e-6;
      const Eigen::Vector3d fd =
          (vec(cursor.force(arr(p + d)).value) - vec(cursor.force(arr(p - d)).value)) / 2e-6;
      worst = std::max(worst, (fd - k.col(a)).norm());
      scale = std::max(scale, k.col(a).norm());
    }
  }
  return scale > 0 ? worst / scale : worst;
}

class LatticeFixture : public ::testing::Test {
 protected:
  explicit LatticeFixture(const std::string& name)
      : dir_(std::filesystem::temp_directory_path() /
             ("hapstate_" + name + "_" + std::to_string(::getpid()))) {}
  void SetUp() override { std::filesystem::create_directories(dir_); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path write(playback::Content content, const std::string& name) {
    const std::filesystem::path f = dir_ / name;
    playback::write_file(std::move(content), f);
    return f;
  }
  // The point at (x, y, z) cell spacings from the field's origin.
  Eigen::Vector3d at(double x, double y, double z) const {
    return {field_.origin[0] + x * h_[0], field_.origin[1] + y * h_[1],
            field_.origin[2] + z * h_[2]};
  }

  const std::filesystem::path dir_;
  const Field field_;
  const Eigen::Vector3d h_{0.5, 0.4, 0.6};
};

}  // namespace hapstate::test_util
