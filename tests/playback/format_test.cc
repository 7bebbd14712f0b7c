// The playback file: round trip, O(1) checks at open (header, section table, sizes),
// verify() (section checksums, cross-references), atomic replacement. Truth: the content
// written, and deliberately damaged copies of the file.
#include "../common/expect_input_error.h"
#include "hapstate/playback.h"
#include "hapstate/playback_c.h"
#include "playback/code_id.h"
#include "synthetic.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

namespace hapstate {
namespace {

namespace fs = std::filesystem;
using test_util::expect_input_error;

class PlaybackFormat : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hapstate_format_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    file_ = dir_ / "playback.bin";
    playback::write_file(test_util::synthetic_content(field_, {0.5, 0.4, 0.6}), file_);
    bytes_ = read(file_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string read(const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  fs::path damaged(const std::string& bytes) {
    const fs::path f = dir_ / "damaged.bin";
    std::ofstream(f, std::ios::binary | std::ios::trunc) << bytes;
    return f;
  }
  // Offset of section `id` in the written file.
  std::uint64_t section_offset(playback::SectionId id) const {
    const auto* table = reinterpret_cast<const playback::SectionEntry*>(bytes_.data() + 64);
    for (int s = 0; s < playback::kSectionCount; ++s)
      if (table[s].id == static_cast<std::uint32_t>(id)) return table[s].offset;
    return 0;
  }

  test_util::Field field_;
  fs::path dir_, file_;
  std::string bytes_;
};

TEST_F(PlaybackFormat, RoundTripKeepsEveryValue) {
  PlaybackFile f(file_);
  f.verify();
  EXPECT_EQ(f.num_configurations(), 125);
  EXPECT_EQ(f.num_view_nodes(), test_util::kSyntheticViewNodes);
  EXPECT_TRUE(f.view_is_all_nodes());
  EXPECT_EQ(f.grid_dims(), (std::array<std::int32_t, 3>{5, 5, 5}));
  EXPECT_EQ(f.grid_lo(), (std::array<std::int32_t, 3>{-2, -2, -2}));
  EXPECT_EQ(f.triangles().size(), 6u);
  // Configuration 124 is check-point (2, 2, 2).
  const Eigen::Vector3d p = field_.origin + Eigen::Vector3d(2 * 0.5, 2 * 0.4, 2 * 0.6);
  const auto force = f.force(124);
  for (int r = 0; r < 3; ++r) EXPECT_EQ(force[r], field_.force(p)[r]);
  const auto k = f.stiffness(124);
  EXPECT_EQ(k[5], field_.jacobian(p)(1, 2));
  const auto u = f.displacements(124);
  EXPECT_EQ(u[3 * 4 + 1], static_cast<float>(test_util::synthetic_displacement(field_, 4, p)[1]));
  ASSERT_TRUE(f.has_displacement_slopes());
  const auto du_dz = f.displacement_slopes(124, 2);
  ASSERT_EQ(du_dz.size(), 3u * test_util::kSyntheticViewNodes);
  EXPECT_EQ(du_dz[3 * 4 + 1],
            static_cast<float>(test_util::synthetic_displacement_slope(field_, 4, p)(1, 2)));
  EXPECT_GT(f.force_change_bound(), 0.0);
  // Every section is 64-byte aligned in the file.
  const auto* table = reinterpret_cast<const playback::SectionEntry*>(bytes_.data() + 64);
  for (int s = 0; s < playback::kSectionCount; ++s) EXPECT_EQ(table[s].offset % 64, 0u);
}

TEST_F(PlaybackFormat, TruncatedFileIsRefusedAtOpen) {
  for (std::size_t keep : {std::size_t{0}, std::size_t{10}, std::size_t{64}, std::size_t{500},
                           bytes_.size() / 2, bytes_.size() - 1}) {
    const fs::path f = damaged(bytes_.substr(0, keep));
    if (keep < 64) {
      expect_input_error([&] { PlaybackFile p(f); },
                         {f.string(), "shorter than the 64-byte header"});
    } else {
      expect_input_error([&] { PlaybackFile p(f); },
                         {f.string(), "truncated", std::to_string(keep)});
    }
  }
  expect_input_error([&] { PlaybackFile p(dir_ / "missing.bin"); }, {"missing.bin", "cannot open"});
}

TEST_F(PlaybackFormat, DamagedHeaderIsRefusedAtOpen) {
  std::string b = bytes_;
  b[0] = 'X';
  expect_input_error([&] { PlaybackFile p(damaged(b)); }, "bad magic");
  b = bytes_;
  b[8] = 12;  // version 12: no sixteenth-spacing points
  expect_input_error([&] { PlaybackFile p(damaged(b)); },
                     "format version 12, this build reads version 13 (run hapstate-index again)");
  b = bytes_;
  b[30] ^= 1;  // section table offset, covered by the header checksum
  expect_input_error([&] { PlaybackFile p(damaged(b)); }, "header checksum mismatch");
}

TEST_F(PlaybackFormat, DamagedSectionTableIsRefusedAtOpen) {
  std::string b = bytes_;
  b[64 + 32 * 4 + 8] ^= 0x40;  // offset of the fifth section
  expect_input_error([&] { PlaybackFile p(damaged(b)); }, "section table checksum mismatch");
}

TEST_F(PlaybackFormat, DamagedMetaIsRefusedAtOpen) {
  std::string b = bytes_;
  b[section_offset(playback::SectionId::kMeta) + 3] ^= 0x10;
  expect_input_error([&] { PlaybackFile p(damaged(b)); }, "meta section checksum mismatch");
}

TEST_F(PlaybackFormat, DamagedDataIsFoundByVerify) {
  for (auto [id, name] :
       {std::pair{playback::SectionId::kDisplacements, "displacements"},
        std::pair{playback::SectionId::kDisplacementSlopes, "displacement slopes"},
        std::pair{playback::SectionId::kTransitions, "transitions"},
        std::pair{playback::SectionId::kForce, "forces"}}) {
    std::string b = bytes_;
    b[section_offset(id) + 17] ^= 0x01;
    const fs::path f = damaged(b);
    PlaybackFile p(f);  // O(1) checks do not read the data
    expect_input_error([&] { p.verify(); },
                       {f.string(), std::string("section '") + name + "' checksum mismatch"});
  }
}

TEST_F(PlaybackFormat, CursorOnDamagedTransitionsStaysFinite) {
  // Transition targets overwritten with garbage: the cursor treats them as missing.
  std::string b = bytes_;
  const std::uint64_t at = section_offset(playback::SectionId::kTransitions);
  for (std::size_t k = 0; k < 26 * 125 * 4; k += 4) {
    const std::int32_t garbage = static_cast<std::int32_t>(1000003 * (k + 7));
    std::memcpy(&b[at + k], &garbage, 4);
  }
  PlaybackFile p(damaged(b));
  HapticCursor cursor(p, Scheme::kHermite);
  for (int s = 0; s < 200; ++s) {
    const Force f = cursor.force({1.0 + 0.02 * s, 2.0 - 0.01 * s, 3.0 + 0.015 * s});
    for (double v : f.value) EXPECT_TRUE(std::isfinite(v));
  }
}

TEST_F(PlaybackFormat, FailedWriteLeavesTheOldFileIntact) {
  playback::Content bad = test_util::synthetic_content(field_, {0.5, 0.4, 0.6});
  bad.meta.dims[1] = 0;
  expect_input_error([&] { playback::write_file(std::move(bad), file_); },
                     "at least 1 check-point");
  playback::Content throws = test_util::synthetic_content(field_, {0.5, 0.4, 0.6});
  throws.displacements = [](std::int32_t c, std::span<float>) {
    if (c == 60) throw InputError("blob unreadable");
  };
  expect_input_error([&] { playback::write_file(std::move(throws), file_); }, "blob unreadable");
  EXPECT_EQ(read(file_), bytes_);
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// The certificate's headline is read only for the file it was measured on, played back by the
// code that measured it (docs/certificate.md: another cursor promises nothing of it).
TEST_F(PlaybackFormat, CertificateIsReadForItsFileAndItsCodeOnly) {
  const std::uint64_t source = PlaybackFile(file_).source_hash();
  EXPECT_FALSE(PlaybackFile(file_).certificate());
  playback::CertificateRecord r{};
  r.paths = 20;
  r.steps_per_path = 30;
  r.force_error_worst[1] = 0.0123;
  auto read_back = [&](std::uint64_t hash, std::uint64_t code) {
    r.measured_source_hash = hash;
    r.measured_code_id = code;
    playback::write_certificate(file_, r);
    return PlaybackFile(file_).certificate();
  };
  const auto own = read_back(source, playback_code_id());
  ASSERT_TRUE(own);
  EXPECT_EQ(own->paths, 20);
  EXPECT_EQ(own->force_error_worst[1], 0.0123);
  EXPECT_FALSE(read_back(source, playback_code_id() ^ 1));  // measured by another cursor
  EXPECT_FALSE(read_back(source, 0));                       // before the code id was recorded
  EXPECT_FALSE(read_back(source ^ 1, playback_code_id()));  // measured on another file
  PlaybackFile(file_).verify();
}

TEST_F(PlaybackFormat, CInterfaceReportsErrors) {
  hs_playback* p = nullptr;
  char error[256] = "";
  ASSERT_EQ(hs_playback_open(damaged(bytes_.substr(0, 100)).c_str(), &p, error, sizeof error), -1);
  EXPECT_EQ(p, nullptr);
  EXPECT_NE(std::string(error).find("truncated"), std::string::npos) << error;
  ASSERT_EQ(hs_playback_open(file_.c_str(), &p, error, sizeof error), 0) << error;
  EXPECT_EQ(hs_playback_verify(p, error, sizeof error), 0);
  EXPECT_EQ(hs_cursor_create(p, 7), nullptr);
  hs_playback_close(p);
  // The same interface from a C program (c_api_test.c).
  const std::string command = std::string(HAPSTATE_C_API_TEST_EXE) + " " + file_.string();
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
}

}  // namespace
}  // namespace hapstate
