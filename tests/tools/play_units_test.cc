// hapstate-play's pieces: the device path sampled at the tick rate, the latency summary and
// the surface VTU writer for frames.
#include "io/surface_vtu.h"
#include "play/tick_path.h"
#include "util/distribution.h"
#include "util/error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace hapstate::play {
namespace {

TEST(TickPath, VisitsThePointsAtTheSpeedLinearlyBetweenThem) {
  // 3 + 4 = 7 mesh units at 2 units/s = 3.5 s: ticks 0..3500 at 1 kHz.
  const TickPath path({{0, 0, 0}, {3, 0, 0}, {3, 4, 0}}, 2.0, 1000.0);
  EXPECT_DOUBLE_EQ(path.length(), 7.0);
  EXPECT_DOUBLE_EQ(path.duration(), 3.5);
  EXPECT_EQ(path.num_ticks(), 3501);
  TickPath::Sampler sampler(path);
  const auto at = [&](std::int64_t tick) { return sampler.position(tick); };
  EXPECT_EQ(at(0), (std::array<double, 3>{0, 0, 0}));
  const auto a = at(750);  // 1.5 units along the first segment
  EXPECT_NEAR(a[0], 1.5, 1e-12);
  EXPECT_NEAR(a[1], 0.0, 1e-12);
  const auto b = at(1500);  // the corner
  EXPECT_NEAR(b[0], 3.0, 1e-12);
  EXPECT_NEAR(b[1], 0.0, 1e-12);
  const auto c = at(2500);  // 2 units up the second segment
  EXPECT_NEAR(c[0], 3.0, 1e-12);
  EXPECT_NEAR(c[1], 2.0, 1e-12);
  const auto d = at(3500);
  EXPECT_NEAR(d[1], 4.0, 1e-12);
  const auto e = at(9999);  // past the end: stays at the last point
  EXPECT_EQ(e, (std::array<double, 3>{3, 4, 0}));
}

TEST(TickPath, OnePointAndRepeatedPointsGiveFiniteTicks) {
  EXPECT_EQ(TickPath({{1, 2, 3}}, 1.0, 1000.0).num_ticks(), 1);
  const TickPath path({{0, 0, 0}, {0, 0, 0}, {1, 0, 0}}, 1.0, 10.0);
  EXPECT_EQ(path.num_ticks(), 11);
  TickPath::Sampler sampler(path);
  for (std::int64_t k = 0; k < path.num_ticks(); ++k)
    EXPECT_NEAR(sampler.position(k)[0], 0.1 * k, 1e-12);
}

TEST(TickPath, RejectsEmptyPathsAndNonPositiveSpeedOrRate) {
  EXPECT_THROW(TickPath({}, 1.0, 1000.0), InputError);
  EXPECT_THROW(TickPath({{0, 0, 0}}, 0.0, 1000.0), InputError);
  EXPECT_THROW(TickPath({{0, 0, 0}}, 1.0, -1.0), InputError);
  EXPECT_THROW(TickPath({{0, 0, 0}, {1e12, 0, 0}}, 1.0, 1000.0), InputError);  // > 1e8 ticks
}

TEST(Distribution, NearestRankPercentiles) {
  std::vector<double> v;
  for (int k = 1000; k >= 1; --k) v.push_back(k);
  const Distribution d = summarize(v);
  EXPECT_EQ(d.median, 500);
  EXPECT_EQ(d.p99, 990);
  EXPECT_EQ(d.p999, 999);
  EXPECT_EQ(d.max, 1000);
  std::vector<double> one{7};
  EXPECT_EQ(summarize(one).p999, 7);
  EXPECT_EQ(summarize(std::span<double>()).max, 0);
}

TEST(SurfaceVtu, WritesTrianglesPositionsAndDisplacements) {
  const auto file = std::filesystem::path(testing::TempDir()) / "surface.vtu";
  const std::vector<float> reference{0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<float> positions{0, 0, 0.5f, 1, 0, 0, 0, 1, 0};
  const std::vector<std::int32_t> triangles{0, 1, 2};
  write_surface_vtu(file, positions, triangles, reference);
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  EXPECT_NE(s.find("<Piece NumberOfPoints=\"3\" NumberOfCells=\"1\">"), std::string::npos);
  // The points are the reference; the displacement carries the deformation (once).
  EXPECT_NE(s.find("format=\"ascii\">\n0 0 0\n1 0 0\n0 1 0\n"), std::string::npos) << s;
  EXPECT_NE(s.find("Name=\"connectivity\" format=\"ascii\">\n0 1 2\n"), std::string::npos);
  EXPECT_NE(s.find("Name=\"types\" format=\"ascii\">\n5\n"), std::string::npos);
  EXPECT_NE(s.find("Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n0 0 "
                   "0.5\n0 0 0\n0 0 0\n"),
            std::string::npos)
      << s;
  std::filesystem::remove(file);
}

TEST(SurfaceVtu, RejectsBadIndicesAndUnwritableFilesNamingTheFile) {
  const std::vector<float> positions{0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<std::int32_t> bad{0, 1, 3};
  try {
    write_surface_vtu("/tmp/never.vtu", positions, bad);
    FAIL() << "accepted an out-of-range vertex";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/tmp/never.vtu"), std::string::npos);
  }
  const std::vector<std::int32_t> good{0, 1, 2};
  EXPECT_THROW(write_surface_vtu("/nonexistent/dir/f.vtu", positions, good), InputError);
}

}  // namespace
}  // namespace hapstate::play
