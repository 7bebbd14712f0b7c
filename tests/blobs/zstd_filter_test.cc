// The zstd filter: registration, the id in the filter pipeline, and the chunk format a foreign
// reader (the standard HDF5 zstd plugin) expects: one zstd frame with the content size.
#include "blobs/zstd_filter.h"
#include "blobs/blob_store.h"
#include "blobs/segment_writer.h"
#include "temp_dir.h"

#include <gtest/gtest.h>
#include <hdf5.h>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <thread>
#include <vector>

namespace hapstate {
namespace {

std::vector<double> smooth_signal(std::size_t n) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = std::round(1000.0 * std::sin(0.001 * i)) / 1000.0;
  return v;
}

TEST(ZstdFilter, RegistrationIsIdempotentAndThreadSafe) {
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) threads.emplace_back([] { register_zstd_filter(); });
  for (auto& t : threads) t.join();
  register_zstd_filter();
  EXPECT_GT(H5Zfilter_avail(kZstdFilterId), 0);
  unsigned int info = 0;
  ASSERT_GE(H5Zget_filter_info(kZstdFilterId, &info), 0);
  EXPECT_NE(info & H5Z_FILTER_CONFIG_ENCODE_ENABLED, 0u);
  EXPECT_NE(info & H5Z_FILTER_CONFIG_DECODE_ENABLED, 0u);
}

TEST(ZstdFilter, SegmentDatasetCarriesFilter32015AndIsSmaller) {
  test_util::TempDir dir("zstd");
  const auto values = smooth_signal(200000);
  SegmentWriterOptions options;
  options.zstd_level = 5;
  SegmentWriter writer(dir.path(), SegmentId{1}, {}, options);
  writer.write("c0/u", values);
  writer.close();

  hid_t file = H5Fopen(writer.path().c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  hid_t dataset = H5Dopen2(file, "u", H5P_DEFAULT);  // the rows of every "<group>/u"
  ASSERT_GE(dataset, 0);
  hid_t dcpl = H5Dget_create_plist(dataset);
  ASSERT_EQ(H5Pget_nfilters(dcpl), 2);
  unsigned flags = 0;
  size_t n_values = 4;
  unsigned values_out[4] = {0, 0, 0, 0};
  char name[128] = {0};
  unsigned config = 0;
  EXPECT_EQ(H5Pget_filter2(dcpl, 0, &flags, &n_values, values_out, sizeof name, name, &config),
            H5Z_FILTER_SHUFFLE);
  n_values = 4;
  EXPECT_EQ(H5Pget_filter2(dcpl, 1, &flags, &n_values, values_out, sizeof name, name, &config),
            32015);
  EXPECT_EQ(n_values, 1u);
  EXPECT_EQ(values_out[0], 5u);  // the level, in cd_values[0]
  EXPECT_NE(std::strstr(name, "Zstandard"), nullptr) << name;

  const hsize_t stored = H5Dget_storage_size(dataset);
  EXPECT_GT(stored, 0u);
  EXPECT_LT(stored, values.size() * sizeof(double) / 4) << "smooth data must compress > 4x";
  H5Pclose(dcpl);
  H5Dclose(dataset);
  H5Fclose(file);

  BlobStore store(dir.path());
  EXPECT_EQ(store.read(SegmentId{1}, "c0/u"), values);
}

// A foreign plugin decodes each chunk with ZSTD_decompress after ZSTD_getFrameContentSize:
// check that a raw chunk we wrote is exactly that.
TEST(ZstdFilter, RawChunkIsOneZstdFrameWithContentSize) {
  test_util::TempDir dir("zstd");
  register_zstd_filter();
  const auto path = dir.path() / "raw.h5";
  std::vector<double> values = smooth_signal(1000);
  hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  hsize_t dims[1] = {values.size()};
  hid_t space = H5Screate_simple(1, dims, nullptr);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(dcpl, 1, dims);
  const unsigned level = 9;
  ASSERT_GE(H5Pset_filter(dcpl, kZstdFilterId, H5Z_FLAG_MANDATORY, 1, &level), 0);
  hid_t dataset = H5Dcreate2(file, "v", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  ASSERT_GE(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  H5Dflush(dataset);

  const hsize_t origin[1] = {0};
  hsize_t chunk_bytes = 0;
  ASSERT_GE(H5Dget_chunk_storage_size(dataset, origin, &chunk_bytes), 0);
  std::vector<char> chunk(chunk_bytes);
  uint32_t filter_mask = 0;
  ASSERT_GE(H5Dread_chunk(dataset, H5P_DEFAULT, origin, &filter_mask, chunk.data()), 0);
  EXPECT_EQ(filter_mask, 0u);
  EXPECT_EQ(ZSTD_getFrameContentSize(chunk.data(), chunk.size()), values.size() * sizeof(double));
  std::vector<double> decoded(values.size());
  EXPECT_EQ(
      ZSTD_decompress(decoded.data(), decoded.size() * sizeof(double), chunk.data(), chunk.size()),
      values.size() * sizeof(double));
  EXPECT_EQ(decoded, values);

  // And the other way: a chunk compressed by a streaming writer (no content size in the frame
  // header) is decoded by our filter.
  std::vector<double> other(values.size());
  for (std::size_t i = 0; i < other.size(); ++i) other[i] = 0.5 * static_cast<double>(i % 17);
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  std::vector<char> frame(ZSTD_compressBound(other.size() * sizeof(double)));
  ZSTD_inBuffer in{other.data(), other.size() * sizeof(double), 0};
  ZSTD_outBuffer out{frame.data(), frame.size(), 0};
  ZSTD_compressStream2(cctx, &out, &in, ZSTD_e_continue);  // size not known up front
  ZSTD_inBuffer none{nullptr, 0, 0};
  ASSERT_EQ(ZSTD_compressStream2(cctx, &out, &none, ZSTD_e_end), 0u);
  ZSTD_freeCCtx(cctx);
  frame.resize(out.pos);
  ASSERT_EQ(ZSTD_getFrameContentSize(frame.data(), frame.size()), ZSTD_CONTENTSIZE_UNKNOWN);
  ASSERT_GE(H5Dwrite_chunk(dataset, H5P_DEFAULT, 0, origin, frame.size(), frame.data()), 0);
  std::vector<double> read_back(values.size());
  ASSERT_GE(H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, read_back.data()),
            0);
  EXPECT_EQ(read_back, other);

  H5Dclose(dataset);
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Fclose(file);
}

}  // namespace
}  // namespace hapstate
