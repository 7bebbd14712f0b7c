// Content hash (XXH64 reference values) and the direction numbering.
#include "util/hash.h"
#include "../blobs/temp_dir.h"
#include "catalogue/direction.h"
#include "util/error.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>

namespace hapstate {
namespace {

TEST(ContentHash, MatchesXxh64ReferenceValues) {
  EXPECT_EQ(content_hash("").value, 0xef46db3751d8e999ULL);
  EXPECT_EQ(content_hash("a").value, 0xd24ec4f1a98c6e5bULL);
  EXPECT_EQ(content_hash("abc").value, 0x44bc2cf5ad770999ULL);
  EXPECT_EQ(content_hash("xxhash").value, 0x32dd38952c4bc720ULL);
  EXPECT_EQ(content_hash("abcdefghijklmnopqrstuvwxyz12345").value, 0x467605901b01d6f6ULL);
  EXPECT_EQ(content_hash("").hex(), "ef46db3751d8e999");
}

TEST(ContentHash, AnySplitGivesTheSameValue) {
  std::string text;
  for (int i = 0; i < 1000; ++i) text += static_cast<char>('a' + (i * 7) % 26);
  const ContentHash whole = content_hash(text);
  for (std::size_t step : {1u, 3u, 8u, 31u, 32u, 33u, 100u}) {
    ContentHasher hasher;
    for (std::size_t at = 0; at < text.size(); at += step) {
      hasher.update(std::string_view(text).substr(at, step));
    }
    EXPECT_EQ(hasher.value(), whole) << "step " << step;
  }
  EXPECT_NE(content_hash(text.substr(0, 999)), whole);
  std::string flipped = text;
  flipped[500] ^= 1;
  EXPECT_NE(content_hash(flipped), whole);
}

TEST(ContentHash, NumbersAreHashedLittleEndian) {
  const unsigned char one_le[8] = {0, 0, 0, 0, 0, 0, 0xf0, 0x3f};  // 1.0
  EXPECT_EQ(ContentHasher().update(1.0).value(),
            content_hash(std::as_bytes(std::span<const unsigned char>(one_le, 8))));
  const unsigned char minus2[8] = {0xfe, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
  EXPECT_EQ(ContentHasher().update(std::int64_t{-2}).value(),
            content_hash(std::as_bytes(std::span<const unsigned char>(minus2, 8))));
}

TEST(ContentHash, FileAndHex) {
  test_util::TempDir dir("hash");
  const auto file = dir.path() / "scene.toml";
  std::string text(200000, 'x');
  text[12345] = 'y';
  std::ofstream(file, std::ios::binary) << text;
  EXPECT_EQ(content_hash_file(file), content_hash(text));
  EXPECT_THROW(content_hash_file(dir.path() / "missing"), InputError);
  const ContentHash h{0x0123456789abcdefULL};
  EXPECT_EQ(h.hex(), "0123456789abcdef");
  EXPECT_EQ(ContentHash::from_hex("0123456789ABCDEF"), h);
  EXPECT_THROW(ContentHash::from_hex("0123"), InputError);
  EXPECT_THROW(ContentHash::from_hex("0123456789abcdeg"), InputError);
}

TEST(Direction, NumberingIsFixed) {
  EXPECT_EQ(Direction(0).offset(), (std::array<int, 3>{-1, -1, -1}));
  EXPECT_EQ(Direction(12).offset(), (std::array<int, 3>{0, 0, -1}));
  EXPECT_EQ(Direction(13).offset(), (std::array<int, 3>{0, 0, 1}));
  EXPECT_EQ(Direction(25).offset(), (std::array<int, 3>{1, 1, 1}));
  EXPECT_EQ(Direction(4).offset(), (std::array<int, 3>{-1, 0, 0}));
  std::set<std::array<int, 3>> seen;
  int faces = 0, edges = 0, corners = 0;
  for (int d = 0; d < Direction::kCount; ++d) {
    const Direction dir(d);
    const auto o = dir.offset();
    seen.insert(o);
    EXPECT_EQ(Direction::from_offset(o[0], o[1], o[2]), dir);
    const auto back = dir.opposite().offset();
    EXPECT_EQ(back, (std::array<int, 3>{-o[0], -o[1], -o[2]}));
    EXPECT_EQ(dir.opposite().index(), 25 - d);
    faces += dir.taxicab_length() == 1;
    edges += dir.taxicab_length() == 2;
    corners += dir.taxicab_length() == 3;
  }
  EXPECT_EQ(seen.size(), 26u);
  EXPECT_EQ(faces, 6);
  EXPECT_EQ(edges, 12);
  EXPECT_EQ(corners, 8);
  EXPECT_THROW(Direction(26), std::out_of_range);
  EXPECT_THROW(Direction(-1), std::out_of_range);
  EXPECT_THROW(Direction::from_offset(0, 0, 0), std::out_of_range);
  EXPECT_THROW(Direction::from_offset(2, 0, 0), std::out_of_range);
}

}  // namespace
}  // namespace hapstate
