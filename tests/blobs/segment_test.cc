// Segment writer and blob store: round trips, provenance, damaged and missing data, garbage.
#include "blobs/blob_store.h"
#include "blobs/segment_writer.h"
#include "temp_dir.h"
#include "util/error.h"

#include "../common/expect_input_error.h"

#include <gtest/gtest.h>

#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cstdio>

#include <cmath>
#include <fstream>
#include <vector>

namespace hapstate {
namespace {

using test_util::TempDir;

std::vector<double> ramp(std::size_t n, double scale) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = scale * std::sin(0.37 * static_cast<double>(i));
  return v;
}

using test_util::expect_input_error;

void write_segment(const std::filesystem::path& dir, SegmentId id, std::size_t n) {
  SegmentWriter writer(dir, id, {"abc", "", "test"});
  writer.write("c" + std::to_string(id.value) + "/u", ramp(n, static_cast<double>(id.value)));
  writer.close();
}

TEST(SegmentName, CanonicalNamesOnly) {
  EXPECT_EQ(segment_file_name(SegmentId{42}), "seg-000042.h5");
  EXPECT_EQ(segment_file_name(SegmentId{1234567}), "seg-1234567.h5");
  EXPECT_EQ(parse_segment_file_name("seg-000042.h5"), SegmentId{42});
  EXPECT_EQ(parse_segment_file_name("seg-1234567.h5"), SegmentId{1234567});
  EXPECT_FALSE(parse_segment_file_name("seg-42.h5"));
  EXPECT_FALSE(parse_segment_file_name("seg-000000.h5"));
  EXPECT_FALSE(parse_segment_file_name("seg-000042.h5.tmp"));
  EXPECT_FALSE(parse_segment_file_name("seg-00004x.h5"));
  EXPECT_TRUE(is_valid_vector_name("c42/u"));
  EXPECT_TRUE(is_valid_vector_name("visual.surface-0"));
  EXPECT_FALSE(is_valid_vector_name("/c42/u"));
  EXPECT_FALSE(is_valid_vector_name("c42//u"));
  EXPECT_FALSE(is_valid_vector_name("c42/../u"));
  EXPECT_FALSE(is_valid_vector_name("c 42"));
  EXPECT_FALSE(is_valid_vector_name(""));
}

TEST(Segment, WriteReadRoundTrip) {
  TempDir dir("seg");
  const auto u = ramp(30001, 1e-3);
  const auto h = ramp(3, 2.5);
  std::vector<float> visual = {1.5f, -2.25f, 3.0f};
  {
    SegmentWriter writer(dir.path(), SegmentId{7}, {"00ff00ff00ff00ff", "", "expand"});
    EXPECT_EQ(writer.path(), dir.path() / "seg-000007.h5");
    writer.write("c1/u", u);
    writer.write("c1/h", h);
    writer.write("c1/t", std::vector<double>{});
    writer.write("c2/u", u, Precision::kFloat32);
    writer.write("c2/visual", visual);
    EXPECT_EQ(writer.num_vectors(), 5u);
    writer.close();
    writer.close();  // idempotent
  }
  BlobStore store(dir.path());
  EXPECT_EQ(store.read(SegmentId{7}, "c1/u"), u);
  EXPECT_EQ(store.read(SegmentId{7}, "c1/h"), h);
  EXPECT_TRUE(store.read(SegmentId{7}, "c1/t").empty());
  EXPECT_EQ(store.size_of(SegmentId{7}, "c1/u"), 30001u);
  const auto as_float = store.read_float32(SegmentId{7}, "c2/u");
  ASSERT_EQ(as_float.size(), u.size());
  for (std::size_t i = 0; i < u.size(); i += 997) EXPECT_EQ(as_float[i], static_cast<float>(u[i]));
  const auto widened = store.read(SegmentId{7}, "c2/u");
  EXPECT_EQ(widened[5], static_cast<double>(static_cast<float>(u[5])));
  EXPECT_EQ(store.read_float32(SegmentId{7}, "c2/visual"), visual);
  EXPECT_TRUE(store.contains(SegmentId{7}, "c1/h"));
  EXPECT_FALSE(store.contains(SegmentId{7}, "c1/x"));
  EXPECT_FALSE(store.contains(SegmentId{7}, "c9/u"));

  const SegmentProvenance p = store.provenance(SegmentId{7});
  EXPECT_EQ(p.scene_hash, "00ff00ff00ff00ff");
  EXPECT_EQ(p.writer_version, "0.1.0");
  EXPECT_EQ(p.stage, "expand");
}

TEST(Segment, RowsOfVaryingLengthIntegersAndAnyNamesRoundTrip) {
  TempDir dir("seg");
  // Touched sets grow and shrink from row to row; indices are int32; names with no group and
  // with nested groups share the leaf's table.
  const std::vector<std::vector<int>> touched = {{3}, {1, 5, 9, 12, 40}, {}, {7, 8}};
  const auto long_row = ramp(70000, 3.0);  // wider than one chunk
  {
    SegmentWriter writer(dir.path(), SegmentId{3}, {});
    for (std::size_t k = 0; k < touched.size(); ++k)
      writer.write("c" + std::to_string(k) + "/touched", std::span<const int>(touched[k]));
    writer.write("x", ramp(5, 1.0));
    writer.write("a/b/x", long_row);
    writer.write("c0/x", ramp(2, 7.0));
    writer.close();
  }
  BlobStore store(dir.path());
  for (std::size_t k = 0; k < touched.size(); ++k) {
    const std::string name = "c" + std::to_string(k) + "/touched";
    const std::vector<double> back = store.read(SegmentId{3}, name);
    EXPECT_EQ(std::vector<int>(back.begin(), back.end()), touched[k]) << name;
    EXPECT_EQ(store.size_of(SegmentId{3}, name), touched[k].size());
    EXPECT_EQ(store.precision_of(SegmentId{3}, name), Precision::kInt32);
  }
  EXPECT_EQ(store.read(SegmentId{3}, "x"), ramp(5, 1.0));
  EXPECT_EQ(store.read(SegmentId{3}, "a/b/x"), long_row);
  EXPECT_EQ(store.read(SegmentId{3}, "c0/x"), ramp(2, 7.0));
  EXPECT_EQ(store.list_vectors(SegmentId{3}),
            (std::vector<std::string>{"a/b/x", "c0/touched", "c0/x", "c1/touched", "c2/touched",
                                      "c3/touched", "x"}));
  EXPECT_FALSE(store.contains(SegmentId{3}, "a/x"));
}

TEST(Segment, FormatOneSegmentIsStillRead) {
  // A segment of an older hapstate: one 1-D dataset per vector, at its name.
  TempDir dir("seg");
  const auto path = dir.path() / "seg-000002.h5";
  const auto u = ramp(100, 2.0);
  {
    hid_t file = H5Fcreate(path.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    hid_t links = H5Pcreate(H5P_LINK_CREATE);
    H5Pset_create_intermediate_group(links, 1);
    const hsize_t n = u.size();
    hid_t space = H5Screate_simple(1, &n, nullptr);
    hid_t data = H5Dcreate2(file, "c5/u", H5T_IEEE_F64LE, space, links, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(H5Dwrite(data, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, u.data()), 0);
    H5Dclose(data);
    H5Sclose(space);
    H5Pclose(links);
    for (auto [name, value] :
         {std::pair{"hapstate_segment_format", 1}, std::pair{"hapstate_complete", 1}}) {
      hid_t scalar = H5Screate(H5S_SCALAR);
      hid_t attribute = H5Acreate2(file, name, H5T_STD_I64LE, scalar, H5P_DEFAULT, H5P_DEFAULT);
      const long long v = value;
      H5Awrite(attribute, H5T_NATIVE_LLONG, &v);
      H5Aclose(attribute);
      H5Sclose(scalar);
    }
    H5Fclose(file);
  }
  BlobStore store(dir.path());
  EXPECT_EQ(store.read(SegmentId{2}, "c5/u"), u);
  EXPECT_EQ(store.size_of(SegmentId{2}, "c5/u"), u.size());
  EXPECT_EQ(store.list_vectors(SegmentId{2}), std::vector<std::string>{"c5/u"});
  EXPECT_FALSE(store.contains(SegmentId{2}, "c5/h"));
}

TEST(Segment, DamagedIndexIsReported) {
  TempDir dir("seg");
  {
    SegmentWriter writer(dir.path(), SegmentId{1}, {});
    writer.write("c1/u", ramp(10, 1.0));
    writer.write("c2/u", ramp(10, 2.0));
    writer.close();
  }
  const auto path = dir.path() / "seg-000001.h5";
  {  // row 1 claims group 7 (there are two groups)
    hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t index = H5Dopen2(file, "hapstate_index/u", H5P_DEFAULT);
    const std::int64_t rows[4] = {0, 10, 7, 10};
    ASSERT_GE(H5Dwrite(index, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows), 0);
    H5Dclose(index);
    H5Fclose(file);
  }
  BlobStore store(dir.path());
  expect_input_error([&] { store.read(SegmentId{1}, "c1/u"); },
                     {path.string(), "damaged segment index", "row 1 of 'u' is out of range"});
}

TEST(Segment, WriterRefusesBadNamesDuplicatesAndOverwrite) {
  TempDir dir("seg");
  write_segment(dir.path(), SegmentId{1}, 10);
  expect_input_error([&] { SegmentWriter w(dir.path(), SegmentId{1}, {}); },
                     {"seg-000001.h5", "already exists"});
  SegmentWriter writer(dir.path(), SegmentId{2}, {});
  writer.write("c2/u", ramp(4, 1.0));
  expect_input_error([&] { writer.write("c2/u", ramp(4, 1.0)); }, {"'c2/u'", "written twice"});
  expect_input_error([&] { writer.write("c2/../u", ramp(4, 1.0)); }, {"invalid name"});
  writer.close();
  EXPECT_THROW(writer.write("c3/u", ramp(4, 1.0)), std::logic_error);
}

TEST(Segment, AbandonedWriterLeavesNoFile) {
  TempDir dir("seg");
  {
    SegmentWriter writer(dir.path(), SegmentId{3}, {});
    writer.write("c1/u", ramp(100, 1.0));
    EXPECT_TRUE(std::filesystem::exists(dir.path() / "seg-000003.h5"));
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "seg-000003.h5"));
}

TEST(Segment, MissingDatasetAndMissingSegmentAreNamed) {
  TempDir dir("seg");
  write_segment(dir.path(), SegmentId{4}, 100);
  BlobStore store(dir.path());
  ::testing::internal::CaptureStderr();
  expect_input_error([&] { store.read(SegmentId{4}, "c9/u"); },
                     {"seg-000004.h5", "vector 'c9/u'", "no such vector"});
  expect_input_error([&] { store.read(SegmentId{4}, "c4/h"); },
                     {"seg-000004.h5", "vector 'c4/h'", "no such vector"});
  expect_input_error([&] { store.read(SegmentId{5}, "c5/u"); },
                     {"seg-000005.h5", "segment file is missing"});
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "") << "HDF5 must not print its stack";
}

TEST(Segment, TruncatedSegmentIsReportedNotPrinted) {
  TempDir dir("seg");
  write_segment(dir.path(), SegmentId{1}, 200000);
  const auto path = dir.path() / "seg-000001.h5";
  const auto size = std::filesystem::file_size(path);
  ASSERT_GT(size, 100000u);
  std::filesystem::resize_file(path, size / 2);
  BlobStore store(dir.path());
  ::testing::internal::CaptureStderr();
  expect_input_error([&] { store.read(SegmentId{1}, "c1/u"); },
                     {path.string(), "truncated or corrupt segment", "HDF5: truncated file"});
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(Segment, CorruptChunkIsReported) {
  TempDir dir("seg");
  write_segment(dir.path(), SegmentId{1}, 1000);
  const auto path = dir.path() / "seg-000001.h5";
  haddr_t offset = 0;
  {  // find where the only chunk of c1/u lives: row 0 of the dataset "u"
    hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t dataset = H5Dopen2(file, "u", H5P_DEFAULT);
    const hsize_t origin[2] = {0, 0};
    unsigned mask = 0;
    hsize_t bytes = 0;
    ASSERT_GE(H5Dget_chunk_info_by_coord(dataset, origin, &mask, &offset, &bytes), 0);
    H5Dclose(dataset);
    H5Fclose(file);
  }
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(offset));
    f.write("garbage!", 8);  // destroys the zstd frame header
  }
  BlobStore store(dir.path());
  ::testing::internal::CaptureStderr();
  expect_input_error([&] { store.read(SegmentId{1}, "c1/u"); },
                     {path.string(), "vector 'c1/u'", "cannot read the data"});
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(Segment, WriterKilledBeforeCloseIsNotReadable) {
  TempDir dir("seg");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    SegmentWriter writer(dir.path(), SegmentId{9}, {});
    writer.write("c9/u", ramp(50000, 1.0));
    ::_exit(0);  // like kill -9 before close(): no destructor, no flush
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(std::filesystem::exists(dir.path() / "seg-000009.h5"));
  BlobStore store(dir.path());
  expect_input_error([&] { store.read(SegmentId{9}, "c9/u"); }, {"seg-000009.h5"});
}

TEST(Segment, CacheEvictionKeepsReadsCorrect) {
  TempDir dir("seg");
  for (int i = 1; i <= 3; ++i) write_segment(dir.path(), SegmentId{i}, 64);
  BlobStore store(dir.path(), 1);
  for (int round = 0; round < 3; ++round) {
    for (int i = 1; i <= 3; ++i) {
      char name[16];  // not "c" + std::to_string(i) + "/u": GCC 12 warns (-Wrestrict) falsely
      std::snprintf(name, sizeof name, "c%d/u", i);
      EXPECT_EQ(store.read(SegmentId{i}, name), ramp(64, i));
    }
  }
}

TEST(Segment, GarbageIsListedAndRemoved) {
  TempDir dir("seg");
  BlobStore store(dir.path());
  EXPECT_EQ(store.next_segment_id(), SegmentId{1});
  for (int i = 1; i <= 3; ++i) write_segment(dir.path(), SegmentId{i}, 16);
  std::ofstream(dir.path() / "notes.txt") << "not a segment";
  std::ofstream(dir.path() / "seg-7.h5") << "not canonical";
  EXPECT_EQ(store.list_segments(), (std::vector<SegmentId>{{1}, {2}, {3}}));
  EXPECT_EQ(store.next_segment_id(), SegmentId{4});
  EXPECT_EQ(store.read(SegmentId{1}, "c1/u"), ramp(16, 1));  // cached handle, then deleted

  const std::set<SegmentId> referenced = {SegmentId{2}};
  EXPECT_EQ(store.unreferenced_segments(referenced),
            (std::vector<std::filesystem::path>{dir.path() / "seg-000001.h5",
                                                dir.path() / "seg-000003.h5"}));
  const auto removed = store.remove_unreferenced_segments(referenced);
  EXPECT_EQ(removed.size(), 2u);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "seg-000001.h5"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "seg-000002.h5"));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "seg-000003.h5"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "notes.txt"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "seg-7.h5"));
  EXPECT_TRUE(store.unreferenced_segments(referenced).empty());
  EXPECT_EQ(store.next_segment_id(), SegmentId{3});
  EXPECT_EQ(store.read(SegmentId{2}, "c2/u"), ramp(16, 2));
}

}  // namespace
}  // namespace hapstate
