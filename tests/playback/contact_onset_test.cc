// The cursor in a contact-onset cell (docs/playback.md, "Contact onset"): a synthetic contact
// file whose body is a tilted plane, clear of the sphere where the clearance g(P) = n . (P - x0)
// is >= 0, with force f = k max(0, -g) d and displacements u_v = max(0, -g) U_v (d, U_v fixed
// vectors). The force is linear in the depth from the onset on and 0 before it, so with the
// onset handled the cursor reproduces it exactly in every cell, the cells the plane cuts
// included; interpolating the free corners' zeros (the same file with the clearance hidden)
// smooths the kink over the cell.
#include "allocation_counter.h"
#include "hapstate/playback.h"
#include "playback/onset_model.h"
#include "synthetic.h"
#include "util/triangle_point.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

namespace hapstate {
namespace {

namespace fs = std::filesystem;

Eigen::Vector3d vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
std::array<double, 3> arr(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

struct Plane {
  test_util::Field grid;  // only its origin (the rest position) is used
  Eigen::Vector3d h{0.5, 0.4, 0.6};
  Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
  Eigen::Vector3d x0 = grid.origin - Eigen::Vector3d(0.1, 0.2, 0.75);  // the rest clear of it
  Eigen::Vector3d d{0.2, -0.1, 1.0};                                   // force per unit depth / k
  double k = 2.5;                                                      // N per mesh unit of depth
  double stiffening = 0;  // the force k (e + stiffening e^2) d at depth e (0: proportional to it)

  // The sphere's radius: the body's surface is the plane n . (P - x0) = -radius (or the roof).
  double radius = 1.0;
  // A roof instead of the plane: two half-planes of slope roof_slope meeting at a ridge along y
  // (at x = x0.x, the sphere touching it at z = x0.z), whose clearance is not a linear function.
  bool roof = false;
  double roof_slope = 0.6;
  double roof_height(double x) const { return x0.z() - radius - roof_slope * std::abs(x - x0.x()); }
  // The roof's triangles (9 doubles each): with roof_tiles 1, 4 far larger than the grid; else
  // each half tiled by roof_tiles x roof_tiles squares of two triangles over 8 x 8 mesh units,
  // about the cells' size, so that each cell lists only those near it.
  int roof_tiles = 1;
  std::vector<double> roof_triangles() const {
    const double L = roof_tiles == 1 ? 50.0 : 4.0, xr = x0.x();
    std::vector<double> out;
    auto add = [&](double xa, double ya, double xb, double yb, double xc, double yc) {
      for (const auto& [x, y] : {std::pair{xa, ya}, std::pair{xb, yb}, std::pair{xc, yc}})
        out.insert(out.end(), {x, y, roof_height(x)});
    };
    const double step = L / roof_tiles;
    for (int side = -1; side <= 1; side += 2)
      for (int i = 0; i < roof_tiles; ++i)
        for (int j = 0; j < 2 * roof_tiles; ++j) {
          const double xa = xr + side * i * step, xb = xr + side * (i + 1) * step;
          const double ya = -L + j * step, yb = ya + step;
          add(xa, ya, xb, ya, xb, yb);
          add(xa, ya, xb, yb, xa, yb);
        }
    return out;
  }
  // The plane as two triangles (its clearance from them is exactly gap()).
  std::vector<double> plane_triangles() const {
    const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u), c = x0 - radius * n;
    std::vector<double> out;
    const double L = 50.0;
    for (const auto& [a, b] : {std::pair{-L, -L}, std::pair{L, -L}, std::pair{L, L},
                               std::pair{-L, -L}, std::pair{L, L}, std::pair{-L, L}}) {
      const Eigen::Vector3d corner = c + a * u + b * v;
      out.insert(out.end(), {corner[0], corner[1], corner[2]});
    }
    return out;
  }
  // The roof's signed distance (< 0 below it) and its gradient, by brute force.
  std::pair<double, Eigen::Vector3d> roof_distance(const Eigen::Vector3d& p) const {
    const std::vector<double> t = roof_triangles();
    TrianglePoint best;
    best.distance = 1e300;
    for (std::size_t k = 0; k < t.size(); k += 9) {
      const TrianglePoint tp = closest_point(Eigen::Vector3d(t[k], t[k + 1], t[k + 2]),
                                             Eigen::Vector3d(t[k + 3], t[k + 4], t[k + 5]),
                                             Eigen::Vector3d(t[k + 6], t[k + 7], t[k + 8]), p);
      if (tp.distance < best.distance) best = tp;
    }
    const double sign = p.z() >= roof_height(p.x()) ? 1.0 : -1.0;
    return {sign * best.distance, sign * (p - best.closest) / best.distance};
  }
  double gap(const Eigen::Vector3d& p) const {
    return roof ? roof_distance(p).first - radius : n.dot(p - x0);
  }
  Eigen::Vector3d gap_gradient(const Eigen::Vector3d& p) const {
    return roof ? roof_distance(p).second : n;
  }
  double depth(const Eigen::Vector3d& p) const { return std::max(0.0, -gap(p)); }
  Eigen::Vector3d force(const Eigen::Vector3d& p) const {
    const double e = depth(p);
    return k * (e + stiffening * e * e) * d;
  }
  Eigen::Matrix3d jacobian(const Eigen::Vector3d& p) const {
    return gap(p) < 0
               ? Eigen::Matrix3d(-k * (1.0 + 2.0 * stiffening * depth(p)) * d * n.transpose())
               : Eigen::Matrix3d::Zero();
  }
  double curvature = 0;  // of the displacements along the depth (0: proportional to it)
  Eigen::Vector3d u(int v, const Eigen::Vector3d& p) const {
    const double e = depth(p);
    return e * Eigen::Vector3d(0.1 * (v + 1), 0.05, -0.02 * v) +
           curvature * e * e * Eigen::Vector3d(0.3, -0.1 * v, 0.2);
  }
  // d u / d depth (0 where the plane is clear).
  Eigen::Vector3d u_per_depth(int v, const Eigen::Vector3d& p) const {
    if (gap(p) >= 0) return Eigen::Vector3d::Zero();
    return Eigen::Vector3d(0.1 * (v + 1), 0.05, -0.02 * v) +
           2.0 * curvature * depth(p) * Eigen::Vector3d(0.3, -0.1 * v, 0.2);
  }
  Eigen::Matrix3d u_slope(int v, const Eigen::Vector3d& p) const {
    return -u_per_depth(v, p) * n.transpose();
  }
};

// The synthetic grid with the plane's data: free check-points (g >= 0) hold zero
// configurations; `hide_clearance`: every check-point reported touching (no onset cells);
// `triangles`: with the rest surface's triangles, from which the cursor measures the clearance
// exactly (else it interpolates the grid points').
// `flat_z`: a planar workspace (one check-point along z, at the rest position's height).
playback::Content plane_content(const Plane& plane, bool hide_clearance, bool triangles = false,
                                bool flat_z = false) {
  playback::Content c = test_util::synthetic_content(plane.grid, plane.h, flat_z);
  c.meta.probe_mode = static_cast<std::int32_t>(playback::ProbeModeCode::kContact);
  const std::size_t n = c.config_checkpoint.size();
  // Configuration g is at grid point g (x-major, indices -2..2; 0 along a flat z).
  const int nk = flat_z ? 1 : 5, klo = flat_z ? 0 : -2;
  auto position = [plane, nk, klo](std::size_t g) {
    const Eigen::Vector3i ijk(int(g / (5 * nk)) - 2, int(g / nk) % 5 - 2, int(g % nk) + klo);
    return Eigen::Vector3d(plane.grid.origin + ijk.cast<double>().cwiseProduct(plane.h));
  };
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p = position(k);
    const bool free = plane.gap(p) >= 0;
    c.config_zero[k] = free ? 1 : 0;
    const Eigen::Matrix3d jac = plane.jacobian(p);
    for (int r = 0; r < 3; ++r) c.force[3 * k + r] = plane.force(p)[r];
    for (int r = 0; r < 9; ++r) c.stiffness[9 * k + r] = jac(r / 3, r % 3);
    c.clearance.push_back(hide_clearance ? -1.0 : plane.gap(p));
    for (int a = 0; a < 3; ++a) c.clearance.push_back(plane.gap_gradient(p)[a]);
  }
  c.onset = playback::onset_corners(c);
  if (triangles)
    playback::add_onset_triangles(&c, plane.roof ? plane.roof_triangles() : plane.plane_triangles(),
                                  plane.radius);
  c.displacements = [plane, position](std::int32_t config, std::span<float> out) {
    for (int v = 0; v < test_util::kSyntheticViewNodes; ++v)
      for (int r = 0; r < 3; ++r)
        out[3 * v + r] = static_cast<float>(plane.u(v, position(config))[r]);
  };
  c.displacement_slopes = [plane, position](std::int32_t config, std::span<float> out) {
    const Eigen::Vector3d p = position(config);
    if (plane.gap(p) >= 0) return;
    for (int v = 0; v < test_util::kSyntheticViewNodes; ++v) {
      const Eigen::Matrix3d du = plane.u_slope(v, p);
      for (int a = 0; a < 3; ++a)
        for (int r = 0; r < 3; ++r)
          out[3 * (a * test_util::kSyntheticViewNodes + v) + r] = static_cast<float>(du(r, a));
    }
  };
  return c;
}

struct Errors {
  double force = 0, stiffness = 0, displacement = 0, clear_force = 0;
  int clear_points = 0, cut_cells = 0;
};

// Walks from rest to 400 random points of the grid in small steps; the largest errors there.
Errors walk(const PlaybackFile& file, const Plane& plane, Scheme scheme) {
  HapticCursor cursor(file, scheme);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Errors e;
  Eigen::Vector3d p = plane.grid.origin;
  std::vector<float> d(3 * test_util::kSyntheticViewNodes);
  for (int step = 0; step < 400; ++step) {
    const Eigen::Vector3d target =
        plane.grid.origin + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(plane.h);
    for (int s = 1; s < 8; ++s) cursor.force(arr(p + (target - p) * s / 8.0));
    p = target;
    const Force f = cursor.force(arr(p));
    e.force = std::max(e.force, (vec(f.value) - plane.force(p)).norm());
    const Eigen::Matrix3d k = plane.jacobian(p);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> got(f.stiffness.data());
    if (std::abs(plane.gap(p)) > 1e-9) e.stiffness = std::max(e.stiffness, (got - k).norm());
    if (plane.gap(p) >= 0) {
      ++e.clear_points;
      e.clear_force = std::max(e.clear_force, vec(f.value).norm());
    }
    // Does the plane cut this cell? (its corners on both sides)
    int below = 0;
    for (int c = 0; c < 8; ++c) {
      Eigen::Vector3d corner;
      for (int a = 0; a < 3; ++a)
        corner[a] = plane.grid.origin[a] + (std::floor((p[a] - plane.grid.origin[a]) / plane.h[a]) +
                                            ((c >> (2 - a)) & 1)) *
                                               plane.h[a];
      below += plane.gap(corner) < 0;
    }
    e.cut_cells += below > 0 && below < 8;
    Snapshot snap;
    cursor.snapshot(&snap);
    displacements(file, snap, d);
    for (int v = 0; v < test_util::kSyntheticViewNodes; ++v)
      e.displacement =
          std::max(e.displacement,
                   (Eigen::Vector3d(d[3 * v], d[3 * v + 1], d[3 * v + 2]) - plane.u(v, p)).norm());
  }
  return e;
}

class ContactOnset : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hapstate_onset_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(playback::Content content, const std::string& name) {
    const fs::path f = dir_ / name;
    playback::write_file(std::move(content), f);
    return f;
  }
  fs::path dir_;
};

TEST_F(ContactOnset, ForceAndDisplacementsAreExactAcrossTheOnset) {
  const Plane plane;
  const double f_max = plane.k * 2.0 * plane.d.norm();  // the order of the largest force
  for (const bool triangles : {false, true})
    for (const Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
      playback::Content content = plane_content(plane, false, triangles);
      ASSERT_EQ(content.onset_cells.empty(), !triangles);
      PlaybackFile file(write(std::move(content), "onset.bin"));
      SCOPED_TRACE(triangles ? "clearance from the triangles" : "interpolated clearance");
      const Errors e = walk(file, plane, scheme);
      std::printf(
          "onset handled: force %.3g, clear %.3g, stiffness %.3g, displacement %.3g N/-/mesh "
          "units; "
          "%d clear points, %d in cut cells\n",
          e.force, e.clear_force, e.stiffness, e.displacement, e.clear_points, e.cut_cells);
      SCOPED_TRACE(scheme == Scheme::kHermite ? "hermite" : "trilinear");
      EXPECT_GT(e.clear_points, 50);
      EXPECT_GT(e.cut_cells, 50);
      EXPECT_EQ(e.clear_force, 0.0);  // exactly 0 where the sphere is clear of the body at rest
      EXPECT_LE(e.force, 1e-12 * f_max);
      if (scheme == Scheme::kHermite) {
        EXPECT_LE(e.stiffness, 1e-10 * plane.k);
      }
      EXPECT_LE(e.displacement, 1e-6);  // float32 storage
    }
}

// The force (and stiffness) recorded half-way through the moves (0 where the sphere is clear
// there) is fitted to what the onset blend returns, not to the interpolated force it blends:
// the plane stays exact with it, in the cut cells too, with the bubbles (forces only) and with
// the half-spacing Hermite cells (forces and stiffness). Fitted to the interpolated force
// directly, the zeros at clear midpoints would bend it (the file without clearance shows the
// size of such errors).
TEST_F(ContactOnset, MidpointForcesKeepTheOnsetExact) {
  const Plane plane;
  const double f_max = plane.k * 2.0 * plane.d.norm();
  for (const bool stiffness : {false, true})
    for (const Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
      playback::Content content = plane_content(plane, false);
      test_util::add_midpoint_forces(&content, plane, stiffness);
      PlaybackFile file(write(std::move(content), "midpoints.bin"));
      file.verify();
      SCOPED_TRACE(std::string(scheme == Scheme::kHermite ? "hermite" : "trilinear") +
                   (stiffness ? ", midpoint stiffness" : ", midpoint forces"));
      const Errors e = walk(file, plane, scheme);
      std::printf("onset with midpoint %s: force %.3g, clear %.3g, stiffness %.3g N/-\n",
                  stiffness ? "stiffness" : "forces", e.force, e.clear_force, e.stiffness);
      EXPECT_GT(e.cut_cells, 50);
      EXPECT_EQ(e.clear_force, 0.0);
      EXPECT_LE(e.force, 1e-12 * f_max);
      if (scheme == Scheme::kHermite) {
        EXPECT_LE(e.stiffness, 1e-10 * plane.k);
      }
    }
}

// Refined cells near the onset (docs/playback.md, "Refined cells"): every cell of the plane's
// grid refined, the cut cells included, with both schemes. A quarter-lattice point's solved force
// is fitted to what the onset blend returns, as a midpoint's is, and where the blend allows no fit
// (clear of the plane, or too close to the onset) the point keeps the half cells' interpolant: the
// plane stays exact in every cell, and exactly 0 where it is clear. Fitted to the interpolated
// force directly, the zeros at clear points would bend it.
TEST_F(ContactOnset, RefinedCellsKeepTheOnsetExact) {
  const Plane plane;
  const double f_max = plane.k * 2.0 * plane.d.norm();
  playback::Content content = plane_content(plane, false);
  test_util::add_midpoint_forces(&content, plane, true);
  std::vector<std::array<int, 3>> every_cell;
  for (int i = -2; i < 2; ++i)
    for (int j = -2; j < 2; ++j)
      for (int k = -2; k < 2; ++k) every_cell.push_back({i, j, k});
  test_util::add_refined_cells(&content, plane, every_cell);
  ASSERT_EQ(content.refined_points.size(), 64u * 12 * playback::kRefinedPoints);
  PlaybackFile file(write(std::move(content), "refined.bin"));
  file.verify();
  for (const Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
    SCOPED_TRACE(scheme == Scheme::kHermite ? "hermite" : "trilinear");
    const Errors e = walk(file, plane, scheme);
    std::printf("onset with refined cells (%s): force %.3g, clear %.3g, stiffness %.3g N/-\n",
                scheme == Scheme::kHermite ? "hermite" : "trilinear", e.force, e.clear_force,
                e.stiffness);
    EXPECT_GT(e.cut_cells, 50);
    EXPECT_EQ(e.clear_force, 0.0);
    EXPECT_LE(e.force, 1e-12 * f_max);
    if (scheme == Scheme::kHermite) {
      EXPECT_LE(e.stiffness, 1e-10 * plane.k);
    }
  }
}

// A corner whose force is off (a ramp of the force just before it, as where a surface triangle
// starts carrying force: docs/contact.md, the liver tip): its depth model, interpolated over the
// cell, would put its error on the onset a cell away. In a refined cell the depth models come from
// the refined points (fit_local_depth_models): near the onset, away from that corner, the plane is
// played back as if the corner were right; without refined cells it is not.
TEST_F(ContactOnset, RefinedPointsKeepAnOffCornerFromTheOnset) {
  const Plane plane;
  const Eigen::Vector3i off(0, 0, -2);  // a touching check-point below the onset
  auto content_with_off_corner = [&](bool refined, bool single = false) {
    playback::Content content = plane_content(plane, false);
    const std::size_t g = std::size_t((off[0] + 2) * 25 + (off[1] + 2) * 5 + (off[2] + 2));
    EXPECT_LT(content.clearance[4 * g], -playback::onset_band(content.meta.spacing));
    for (int r = 0; r < 3; ++r) content.force[3 * g + r] *= 1.3;
    for (int e = 0; e < 9; ++e) content.stiffness[9 * g + e] *= 1.3;
    content.onset = playback::onset_corners(content);
    test_util::add_midpoint_forces(&content, plane, true);
    if (refined) {
      std::vector<std::array<int, 3>> cells;
      for (int i = -1; i <= 0; ++i)
        for (int j = -1; j <= 0; ++j)
          if (!single || (i == 0 && j == 0)) cells.push_back({off[0] + i, off[1] + j, off[2]});
      test_util::add_refined_cells(&content, plane, cells);
    }
    return content;
  };
  PlaybackFile refined(write(content_with_off_corner(true), "off_refined.bin"));
  PlaybackFile coarse(write(content_with_off_corner(false), "off_coarse.bin"));
  refined.verify();
  const double band = playback::onset_band(plane.h.data());
  for (const Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
    SCOPED_TRACE(scheme == Scheme::kHermite ? "hermite" : "trilinear");
    double largest[2] = {0, 0};
    int points = 0;
    for (int which = 0; which < 2; ++which) {
      HapticCursor cursor(which == 0 ? refined : coarse, scheme);
      std::mt19937_64 rng(5);
      std::uniform_real_distribution<double> u(-0.95, 0.95), up(0.0, 0.95);
      Eigen::Vector3d previous = plane.grid.origin;
      int n = 0;
      while (n < 300) {
        // In the four cells above the off corner, within the band, a quarter cell or more from
        // the corner (the quarter cells beside it interpolate its model). t: cells from it.
        const Eigen::Vector3d t(u(rng), u(rng), up(rng));
        const Eigen::Vector3d p =
            plane.grid.origin + (off.cast<double>() + t).cwiseProduct(plane.h);
        const double d = plane.depth(p);
        if (!(d > 0.0 && d < band) || t.cwiseAbs().maxCoeff() < 0.25) continue;
        ++n;
        for (int s = 1; s < 8; ++s) cursor.force(arr(previous + (p - previous) * s / 8.0));
        previous = p;
        const Force f = cursor.force(arr(p));
        const double err = (vec(f.value) - plane.force(p)).norm();
        largest[which] = std::max(largest[which], err);
      }
      points += n;
    }
    // Relative to the force a band deep (the onset's scale: the force grows from 0 there).
    const double scale = plane.k * band * plane.d.norm();
    std::printf(
        "an off corner (force 1.3x), %d points within the band: largest error %.3g of "
        "the force a band deep with refined cells, %.3g without\n",
        points / 2, largest[0] / scale, largest[1] / scale);
    EXPECT_GT(largest[1], 0.04 * scale);  // the check has teeth: the corner's model reaches it
    // Measured: 0.020 against 0.054 (trilinear), 0.020 against 0.047 (Hermite); what remains
    // sits within half a cell of the corner (where the half cells' data still carry it).
    EXPECT_LT(largest[0], 0.5 * largest[1]);
    // One refined cell with the off corner at its lowest corner: its faces through that corner
    // are shared with cells that are not refined, which interpolate the corner's model. There
    // the refined cell takes the corners' models too, so the force does not jump across them
    // within the band (with the refined points' models on those faces it would: the corner is
    // 1.3x off).
    PlaybackFile single(write(content_with_off_corner(true, true), "off_single.bin"));
    HapticCursor cursor(single, scheme);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(0.0, 0.5);
    double jump = 0;
    int crossings = 0;
    while (crossings < 100) {
      const int axis = crossings % 2;  // the faces x = off.x and y = off.y
      Eigen::Vector3d t(u(rng), u(rng), u(rng));
      t[axis] = 0.0;
      const Eigen::Vector3d p = plane.grid.origin + (off.cast<double>() + t).cwiseProduct(plane.h);
      if (!(plane.depth(p) > 0.0 && plane.depth(p) < band)) continue;
      ++crossings;
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[axis] = 1e-9 * plane.h[axis];
      cursor.force(arr(p - 1e3 * e));
      const Eigen::Vector3d before = vec(cursor.force(arr(p - e)).value);
      const Eigen::Vector3d after = vec(cursor.force(arr(p + e)).value);
      jump = std::max(jump, (after - before).norm());
    }
    std::printf(
        "across a refined cell's faces shared with cells that are not, within the band: "
        "largest jump %.3g of the force a band deep\n",
        jump / scale);
    EXPECT_LT(jump, 1e-6 * scale);
  }
}

// The plane's file with its force, stiffness and displacements half-way through the moves.
playback::Content plane_midpoint_content(const Plane& plane) {
  playback::Content content = plane_content(plane, false);
  test_util::add_midpoint_forces(&content, plane, true);
  test_util::add_midpoint_displacements(
      &content, [plane](int v, const Eigen::Vector3d& p) { return plane.u(v, p); },
      [plane](int v, const Eigen::Vector3d& p) { return plane.u_slope(v, p); });
  return content;
}

// The displacements half-way through the moves are fitted through the onset blend as the force
// is: with displacements that are not proportional to the depth (the depth model is then not
// exact), the snapshot returns the stored displacements at every midpoint, also inside the band
// where the blend mixes in the depth model; used as they are there, they would be off by
// (1 - R) (D - u).
TEST_F(ContactOnset, MidpointDisplacementsAreFittedThroughTheBlend) {
  Plane plane;
  plane.curvature = 0.8;
  PlaybackFile file(write(plane_midpoint_content(plane), "midpoint_displacements.bin"));
  file.verify();
  HapticCursor cursor(file, Scheme::kHermite);
  std::vector<float> d(3 * test_util::kSyntheticViewNodes);
  Eigen::Vector3d p = plane.grid.origin;
  double worst = 0;
  int fitted = 0;
  for (int i = -4; i < 4; ++i)
    for (int j = -4; j < 4; ++j)
      for (int k = -4; k < 4; ++k) {
        if ((i & 1) == 0 && (j & 1) == 0 && (k & 1) == 0) continue;  // a check-point
        const Eigen::Vector3d target =
            plane.grid.origin + 0.5 * Eigen::Vector3d(i, j, k).cwiseProduct(plane.h);
        for (int s = 1; s <= 8; ++s) cursor.force(arr(p + (target - p) * s / 8.0));
        p = target;
        Snapshot snap;
        cursor.snapshot(&snap);
        int point = 0;  // the probe's lattice point in the cell the cursor holds
        for (int a = 0; a < 3; ++a)
          point = 3 * point + int(std::lround(2.0 * snap.cell_position[a]));
        if (snap.midpoint[point] == 0) continue;
        const double R = snap.midpoint_blend[point][0];
        fitted += R > 0.0 && R < 1.0;
        displacements(file, snap, d);
        double e = 0;
        for (int v = 0; v < test_util::kSyntheticViewNodes; ++v)
          e = std::max(
              e, (Eigen::Vector3d(d[3 * v], d[3 * v + 1], d[3 * v + 2]) - plane.u(v, p)).norm());
        worst = std::max(worst, e);
      }
  std::printf("midpoint displacements at the midpoints: largest error %.3g, %d inside the band\n",
              worst, fitted);
  EXPECT_GT(fitted, 5);
  EXPECT_LE(worst, 1e-5);  // float32 storage
  // Displacements proportional to the depth are reproduced everywhere, between the lattice
  // points too (where the fitted slopes enter), and the body stays at rest wherever the probe is
  // clear of it (also in a half cell with a midpoint inside the body).
  plane.curvature = 0.0;
  PlaybackFile linear_file(write(plane_midpoint_content(plane), "linear_midpoints.bin"));
  const Errors e = walk(linear_file, plane, Scheme::kHermite);
  EXPECT_GT(e.clear_points, 50);
  EXPECT_GT(e.cut_cells, 50);
  EXPECT_LE(e.displacement, 1e-6);  // float32 storage
}

// A force that stiffens with the depth, k (e + s e^2) d: every touching configuration's depth
// model d (a + b d) takes its slope along the depth from its stiffness, so it is the force itself
// (a = k d, b = k s d), and just past the onset, where the blend is almost all depth model, the
// cursor follows the force; with the force per unit depth f / d of each configuration (the model
// of format 11) it is off by k s d_t e at depth e, d_t the configuration's depth.
TEST_F(ContactOnset, DepthModelFollowsAForceThatStiffensWithTheDepth) {
  Plane plane;
  plane.stiffening = 1.5;  // per mesh unit: at the deepest check-point (~1.1) 2.6 x the slope
  playback::Content content = plane_content(plane, false);
  int deep = 0;
  for (std::size_t c = 0; c < content.onset.size(); ++c) {
    const playback::OnsetCorner& o = content.onset[c];
    // Every configuration with a depth model (a free check-point without touching neighbours: q 0)
    if (o.depth_source < 0 || (o.depth_source == int(c) && content.config_zero[c] == 1)) continue;
    ++deep;
    for (int r = 0; r < 3; ++r) {
      EXPECT_NEAR(o.per_depth[r], plane.k * plane.d[r], 1e-12) << "configuration " << c;
      EXPECT_NEAR(o.per_depth_squared[r], plane.k * plane.stiffening * plane.d[r], 1e-12)
          << "configuration " << c;
    }
  }
  EXPECT_GT(deep, 60);
  // The same data with the linear model: q = f / d at every touching configuration.
  playback::Content linear = content;
  for (std::size_t c = 0; c < linear.onset.size(); ++c) {
    playback::OnsetCorner& o = linear.onset[c];
    if (o.depth_source < 0) continue;
    const double e = -linear.clearance[4 * std::size_t(linear.config_checkpoint[o.depth_source])];
    for (int r = 0; r < 3; ++r) {
      o.per_depth[r] = plane.k * (1.0 + plane.stiffening * e) * plane.d[r];
      o.per_depth_squared[r] = 0.0;
    }
  }
  PlaybackFile file(write(std::move(content), "stiffening.bin"));
  PlaybackFile linear_file(write(std::move(linear), "linear.bin"));
  // Random points just past the onset (depth below a tenth of the band, h / 20): relative errors.
  const double shallow = 0.1 * 0.5 * plane.h.minCoeff();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.9, 1.9);
  double worst = 0, worst_linear = 0;
  int points = 0;
  HapticCursor cursor(file, Scheme::kHermite), linear_cursor(linear_file, Scheme::kHermite);
  Eigen::Vector3d previous = plane.grid.origin;
  while (points < 200) {
    Eigen::Vector3d p =
        plane.grid.origin + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(plane.h);
    p -=
        (plane.gap(p) + shallow * std::uniform_real_distribution<double>(0.01, 1.0)(rng)) * plane.n;
    if ((p - plane.grid.origin).cwiseQuotient(plane.h).cwiseAbs().maxCoeff() > 1.95) continue;
    ++points;
    for (int step = 1; step < 8; ++step) {
      cursor.force(arr(previous + (p - previous) * step / 8.0));
      linear_cursor.force(arr(previous + (p - previous) * step / 8.0));
    }
    previous = p;
    const Eigen::Vector3d exact = plane.force(p);
    worst = std::max(worst, (vec(cursor.force(arr(p)).value) - exact).norm() / exact.norm());
    worst_linear = std::max(worst_linear,
                            (vec(linear_cursor.force(arr(p)).value) - exact).norm() / exact.norm());
  }
  std::printf(
      "stiffening force just past the onset: largest relative error %.3g (linear model %.3g)\n",
      worst, worst_linear);
  // Not 0: the blend's small share of the interpolated force, which is not exact in cut cells.
  EXPECT_LE(worst, 0.05);
  EXPECT_GE(worst_linear, 10 * worst);
}

// A stiffness that is one-sided at a kink (here 7x or -3x the slope) at a configuration
// shallower than the band: its depth model stays sane over the band, where the cursor uses it
// (its slope >= 0, its quadratic term no larger than its linear one): extrapolated from a shallow
// depth, b = beta f / d^2 would otherwise grow as 1 / d.
TEST_F(ContactOnset, DepthModelOfAShallowConfigurationIsLimitedOverTheBand) {
  const Plane plane;
  const double band = playback::kOnsetBandSpacings * plane.h.minCoeff();
  for (const double factor : {7.0, -3.0}) {
    playback::Content c = plane_content(plane, false);
    int checked = 0;
    for (std::size_t k = 0; k < c.onset.size(); ++k) {
      const double d = -c.clearance[4 * std::size_t(c.config_checkpoint[k])];
      if (c.config_zero[k] == 1 || d <= 1e-3 * plane.h.minCoeff() || d >= band) continue;
      for (int r = 0; r < 9; ++r) c.stiffness[9 * k + r] *= factor;
      ++checked;
    }
    ASSERT_GT(checked, 0);
    const std::vector<playback::OnsetCorner> onset = playback::onset_corners(c);
    for (std::size_t k = 0; k < onset.size(); ++k) {
      const double d = -c.clearance[4 * std::size_t(c.config_checkpoint[k])];
      if (c.config_zero[k] == 1 || d <= 1e-3 * plane.h.minCoeff() || d >= band) continue;
      const Eigen::Vector3d a(onset[k].per_depth), b(onset[k].per_depth_squared);
      const Eigen::Vector3d f(&c.force[3 * k]);
      SCOPED_TRACE("stiffness x " + std::to_string(factor) + ", depth " + std::to_string(d));
      EXPECT_NEAR((d * (a + b * d) - f).norm(), 0.0, 1e-12 * f.norm());  // exact at its depth
      EXPECT_GE((a + 2.0 * band * b).dot(f), -1e-12 * f.squaredNorm());  // slope >= 0 at band
      EXPECT_LE(band * b.norm(), a.norm() * (1.0 + 1e-12));              // b band <= a
    }
  }
}

// A body whose clearance is not linear (a roof: two half-planes meeting at a ridge): the
// clearance interpolated from the grid points is off between them, so the force starts slightly
// early or late; measured from the rest triangles it is exact: the force is 0 exactly where the
// sphere is clear of the body and not 0 where it is not.
TEST_F(ContactOnset, TheRestTrianglesMakeTheOnsetExact) {
  Plane plane;
  plane.roof = true;
  plane.roof_tiles = 8;  // 512 triangles of 0.5 mesh units
  {
    const playback::Content content = plane_content(plane, false, true);
    int cells = 0;
    for (std::size_t g = 0; g + 1 < content.onset_cells.size(); ++g)
      cells += content.onset_cells[g + 1] > content.onset_cells[g];
    const double mean = double(content.onset_triangle_list.size()) / std::max(cells, 1);
    std::printf("roof of %zu triangles: %d cells list %.1f of them on average\n",
                plane.roof_triangles().size() / 9, cells, mean);
    EXPECT_GT(cells, 10);
    EXPECT_LT(mean, 0.25 * double(plane.roof_triangles().size() / 9));  // the lists are pruned
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.9, 1.9), near(-0.02, 0.02);
  int wrong[2] = {0, 0}, points = 0;
  double largest_clear_force[2] = {0, 0};
  PlaybackFile interpolated(write(plane_content(plane, false, false), "interpolated.bin"));
  PlaybackFile exact(write(plane_content(plane, false, true), "exact.bin"));
  HapticCursor cursors[2] = {HapticCursor(interpolated, Scheme::kHermite),
                             HapticCursor(exact, Scheme::kHermite)};
  Eigen::Vector3d previous = plane.grid.origin;
  while (points < 400) {
    // A point within 0.02 of the onset (g = 0), moved there along z.
    Eigen::Vector3d p =
        plane.grid.origin + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(plane.h);
    const double target = near(rng);
    for (int it = 0; it < 60; ++it) p.z() -= plane.gap(p) - target;  // |dg/dz| > 0.85
    if ((p - plane.grid.origin).cwiseQuotient(plane.h).cwiseAbs().maxCoeff() > 1.95) continue;
    if (std::abs(plane.gap(p) - target) > 1e-12) continue;
    ++points;
    for (int which = 0; which < 2; ++which) {
      for (int step = 1; step < 8; ++step)
        cursors[which].force(arr(previous + (p - previous) * step / 8.0));
      const double f = vec(cursors[which].force(arr(p)).value).norm();
      const bool clear = plane.gap(p) >= 0;
      wrong[which] += clear ? f != 0.0 : f == 0.0;
      if (clear) largest_clear_force[which] = std::max(largest_clear_force[which], f);
    }
    previous = p;
  }
  std::printf(
      "roof, 400 points within 0.02 of the onset: force on the wrong side of it at %d "
      "(interpolated clearance, largest force where clear %.3g N), %d (rest triangles)\n",
      wrong[0], largest_clear_force[0], wrong[1]);
  EXPECT_GT(wrong[0], 10);  // the check has teeth: the interpolated clearance is off here
  EXPECT_EQ(wrong[1], 0);
  EXPECT_EQ(largest_clear_force[1], 0.0);
}

// A planar workspace (one check-point along z) whose plane the roof cuts: the cells are flat,
// and the rest triangles still put the force exactly where the sphere touches, on both schemes.
TEST_F(ContactOnset, TheRestTrianglesServeAFlatWorkspace) {
  Plane plane;
  plane.roof = true;
  plane.roof_tiles = 8;
  // The ridge 0.95 below the plane of centres: the sphere touches it (the clearance measured to
  // the ridge itself, not linear) where |x - x0.x| < sqrt(1 - 0.95^2).
  plane.x0 = plane.grid.origin + Eigen::Vector3d(0.5, 0.0, 0.05);
  const double onset = std::sqrt(1.0 - 0.95 * 0.95);
  const playback::Content content = plane_content(plane, false, true, true);
  ASSERT_EQ(content.meta.dims[2], 1);
  ASSERT_FALSE(content.onset_triangle_list.empty());
  PlaybackFile exact(write(content, "flat.bin"));
  exact.verify();
  PlaybackFile interpolated(write(plane_content(plane, false, false, true), "flat_i.bin"));
  std::uniform_real_distribution<double> u(-1.95, 1.95), near(-0.02, 0.02);
  int wrong_interpolated = 0;
  for (const Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite})
    for (const bool triangles : {true, false}) {
      SCOPED_TRACE(scheme == Scheme::kHermite ? "hermite" : "trilinear");
      SCOPED_TRACE(triangles ? "rest triangles" : "interpolated clearance");
      std::mt19937_64 rng(11);
      HapticCursor cursor(triangles ? exact : interpolated, scheme);
      int wrong = 0, touching = 0, clear = 0;
      Eigen::Vector3d previous = plane.grid.origin;
      for (int n = 0; n < 400; ++n) {
        // Every other point within 0.02 (along x) of the onset.
        Eigen::Vector3d p =
            plane.grid.origin + Eigen::Vector3d(u(rng) * plane.h.x(), u(rng) * plane.h.y(), 0.0);
        if (n % 2 == 1)
          p.x() = plane.x0.x() + (p.x() < plane.x0.x() ? -1 : 1) * (onset + near(rng));
        for (int s = 1; s < 8; ++s) cursor.force(arr(previous + (p - previous) * s / 8.0));
        previous = p;
        const Force f = cursor.force(arr(p));
        ASSERT_TRUE(std::isfinite(f.value[0]) && std::isfinite(f.value[1]) &&
                    std::isfinite(f.value[2]));
        const bool is_clear = plane.gap(p) >= 0, zero = vec(f.value).norm() == 0.0;
        (is_clear ? clear : touching) += 1;
        wrong += is_clear ? !zero : zero;
      }
      std::printf("flat workspace, %s: %d points clear, %d touching, %d on the wrong side\n",
                  triangles ? "rest triangles" : "interpolated clearance", clear, touching, wrong);
      EXPECT_GT(clear, 50);
      EXPECT_GT(touching, 50);
      if (triangles) {
        EXPECT_EQ(wrong, 0);
      } else {
        wrong_interpolated += wrong;
      }
    }
  EXPECT_GT(wrong_interpolated, 5);  // the check has teeth: the interpolated clearance is off
}

// Sections 24-26 are checked where they are written (hapstate-index refuses to write a list
// that points outside the triangles); in a file damaged afterwards, which opens (the check at
// open is O(1): sizes only), verify() names the problem and the cursor reads no triangle outside
// the section (it skips an index out of range: run under AddressSanitizer in CI).
TEST_F(ContactOnset, DamagedOnsetListsAreRefusedOrSkipped) {
  Plane plane;
  plane.roof = true;
  plane.roof_tiles = 4;
  playback::Content bad = plane_content(plane, false, true);
  ASSERT_FALSE(bad.onset_triangle_list.empty());
  bad.onset_triangle_list[0] = 1 << 20;
  try {
    playback::write_file(std::move(bad), dir_ / "bad.bin");
    ADD_FAILURE() << "a list out of range was written";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("an onset triangle index is out of range"),
              std::string::npos)
        << e.what();
  }
  const playback::Content content = plane_content(plane, false, true);
  const fs::path file = write(content, "lists.bin");
  // Every list entry set to a huge index, in place (the section's checksum no longer matches).
  std::string bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const auto* table = reinterpret_cast<const playback::SectionEntry*>(bytes.data() + 64);
  std::uint64_t offset = 0, size = 0;
  for (int k = 0; k < playback::kSectionCount; ++k)
    if (table[k].id == static_cast<std::uint32_t>(playback::SectionId::kOnsetTriangleList))
      offset = table[k].offset, size = table[k].bytes;
  ASSERT_GT(size, 0u);
  for (std::uint64_t b = 0; b < size; b += 4) {
    const std::int32_t huge = 1 << 28;
    std::memcpy(bytes.data() + offset + b, &huge, 4);
  }
  const fs::path damaged = dir_ / "damaged.bin";
  std::ofstream(damaged, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  PlaybackFile opened(damaged);  // sizes only at open
  EXPECT_THROW(opened.verify(), InputError);
  HapticCursor cursor(opened, Scheme::kHermite);
  for (int n = 0; n < 2000; ++n) {
    const double t = 1e-2 * n;
    const Force f = cursor.force(
        arr(plane.grid.origin + Eigen::Vector3d(0.8 * std::sin(t), 0.6 * std::cos(1.3 * t),
                                                -0.7 + 0.6 * std::sin(0.7 * t))));
    ASSERT_TRUE(std::isfinite(f.value[0]) && std::isfinite(f.value[1]) &&
                std::isfinite(f.value[2]));
  }
}

TEST_F(ContactOnset, WithoutTheClearanceTheKinkIsSmoothedOverTheCell) {
  // The check that the test above can fail: the same data with every check-point reported
  // touching interpolates the free corners' zeros across the onset.
  const Plane plane;
  PlaybackFile file(write(plane_content(plane, true), "hidden.bin"));
  const double f_max = plane.k * 2.0 * plane.d.norm();
  for (const Scheme scheme : {Scheme::kTrilinear, Scheme::kHermite}) {
    const Errors e = walk(file, plane, scheme);
    std::printf("clearance hidden: force %.3g, clear %.3g (f_max %.3g)\n", e.force, e.clear_force,
                f_max);
    EXPECT_GT(e.force, 0.02 * f_max);
    EXPECT_GT(e.clear_force, 0.01 * f_max);
  }
}

TEST_F(ContactOnset, ForceAndSnapshotDoNotAllocate) {
  // The onset cells' clearance (from the rest triangles), blend and secant corners are
  // fixed-size data too.
  const Plane plane;
  playback::Content content = plane_content(plane, false, true);
  test_util::add_midpoint_forces(&content, plane);  // the bubble fit in onset cells too
  PlaybackFile file(write(std::move(content), "alloc.bin"));
  std::vector<float> pos(3 * test_util::kSyntheticViewNodes);
  Snapshot snap;
  int onset_steps = 0;
  // Made before counting: a cursor allocates its state once, at construction.
  HapticCursor trilinear(file, Scheme::kTrilinear), hermite(file, Scheme::kHermite);
  g_allocations = 0;
  g_counting = true;
  for (HapticCursor* c : {&trilinear, &hermite}) {
    HapticCursor& cursor = *c;
    for (int n = 0; n < 20000; ++n) {
      const double t = 1e-3 * n;
      const Eigen::Vector3d p =
          plane.grid.origin + Eigen::Vector3d(0.8 * std::sin(t), 0.6 * std::cos(1.3 * t),
                                              -0.7 + 0.6 * std::sin(0.7 * t));
      cursor.force(arr(p));
      onset_steps += std::abs(plane.gap(p)) < 0.25 ? 1 : 0;
      if (n % 16 == 0) {
        cursor.snapshot(&snap);
        deform(file, snap, pos);
      }
    }
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(onset_steps, 1000);
}

}  // namespace
}  // namespace hapstate
