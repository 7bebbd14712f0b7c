#include "blobs/segment_writer.h"

#include "blobs/hdf5_support.hpp"
#include "blobs/packed_layout.hpp"
#include "blobs/zstd_filter.h"
#include "util/error.h"
#include "util/version.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace hapstate {

using blobs_detail::Hid;
using blobs_detail::QuietErrors;
using blobs_detail::take_hdf5_error;

namespace {

// fsync of a file or a directory by name; throws EnvironmentError naming it on failure.
void sync_path(const std::filesystem::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) {
    throw EnvironmentError(path.string() + ": cannot open for fsync: " + os_error_text(errno));
  }
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throw EnvironmentError(path.string() + ": fsync failed: " + os_error_text(err));
}

}  // namespace

struct SegmentWriter::Impl {
  // One 2-D dataset: the vectors of one leaf name and storage type, a row each.
  struct Table {
    std::string dataset;
    hid_t file_type;
    Hid handle;
    hsize_t rows = 0, width = 0;
    std::vector<std::int64_t> index;  // per row: group, length
  };
  std::filesystem::path blobs_dir;
  std::filesystem::path path;
  SegmentId id;
  SegmentWriterOptions options;
  Hid file;
  std::set<std::string, std::less<>> names;
  std::vector<std::string> groups;
  std::map<std::string, std::int64_t, std::less<>> group_index;
  std::map<std::pair<std::string, hid_t>, Table> tables;  // by (leaf, file type)
  bool closed = false;

  void write_row(std::string_view name, const void* data, std::size_t count, hid_t file_type,
                 hid_t memory_type);
  Table& table(const std::string& leaf, hid_t file_type, std::size_t first_width,
               const std::string& where);
  void write_index();
};

SegmentWriter::Impl::Table& SegmentWriter::Impl::table(const std::string& leaf, hid_t file_type,
                                                       std::size_t first_width,
                                                       const std::string& where) {
  const auto key = std::make_pair(leaf, file_type);
  if (auto it = tables.find(key); it != tables.end()) return it->second;
  if (leaf == blobs_detail::kIndexGroup) throw InputError(where + ": reserved name");
  // The first table of a leaf is named after it; another storage type of the same leaf gets
  // a suffix.
  bool taken = false;
  for (const auto& [k, t] : tables) taken = taken || k.first == leaf;
  Table t;
  t.dataset = taken ? leaf + (file_type == H5T_IEEE_F32LE  ? ".f32"
                              : file_type == H5T_STD_I32LE ? ".i32"
                                                           : ".f64")
                    : leaf;
  t.file_type = file_type;
  const hsize_t dims[2] = {0, 0};
  const hsize_t max_dims[2] = {H5S_UNLIMITED, H5S_UNLIMITED};
  Hid space(H5Screate_simple(2, dims, max_dims));
  Hid create(H5Pcreate(H5P_DATASET_CREATE));
  // One chunk per row (a configuration's vector decompresses alone), at least 64 values wide
  // so that short, varying rows (touched sets) are not split into many chunks.
  const hsize_t chunk[2] = {
      1, static_cast<hsize_t>(std::clamp<std::size_t>(first_width, 64, options.chunk_elements))};
  const unsigned level = static_cast<unsigned>(options.zstd_level);
  const bool ok = space.valid() && create.valid() && H5Pset_chunk(create.get(), 2, chunk) >= 0 &&
                  H5Pset_shuffle(create.get()) >= 0 &&
                  H5Pset_filter(create.get(), static_cast<H5Z_filter_t>(kZstdFilterId),
                                H5Z_FLAG_MANDATORY, 1, &level) >= 0;
  if (!ok) blobs_detail::throw_hdf5_write_failure(where + ": cannot set up the dataset");
  t.handle = Hid(H5Dcreate2(file.get(), t.dataset.c_str(), file_type, space.get(), H5P_DEFAULT,
                            create.get(), H5P_DEFAULT));
  if (!t.handle.valid() ||
      !blobs_detail::write_string_attribute(t.handle.get(), "hapstate_leaf", leaf))
    blobs_detail::throw_hdf5_write_failure(where + ": cannot create the dataset");
  return tables.emplace(key, std::move(t)).first->second;
}

void SegmentWriter::Impl::write_row(std::string_view name, const void* data, std::size_t count,
                                    hid_t file_type, hid_t memory_type) {
  if (closed) throw std::logic_error("SegmentWriter::write after close()");
  const std::string where = path.string() + ": vector '" + std::string(name) + "'";
  if (!is_valid_vector_name(name)) {
    throw InputError(where + ": invalid name (parts of [A-Za-z0-9_.-] separated by '/')");
  }
  if (names.contains(name)) throw InputError(where + ": written twice");
  QuietErrors quiet;
  const auto [group, leaf] = blobs_detail::split_vector_name(name);
  Table& t = table(leaf, file_type, count, where);
  const hsize_t width = std::max<hsize_t>(t.width, count);
  const hsize_t dims[2] = {t.rows + 1, width};
  if (H5Dset_extent(t.handle.get(), dims) < 0)
    blobs_detail::throw_hdf5_write_failure(where + ": cannot extend the dataset");
  if (count > 0) {
    Hid space(H5Dget_space(t.handle.get()));
    const hsize_t start[2] = {t.rows, 0}, size[2] = {1, count};
    const hsize_t memory_size[1] = {count};
    Hid memory(H5Screate_simple(1, memory_size, nullptr));
    if (!space.valid() || !memory.valid() ||
        H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, size, nullptr) < 0 ||
        H5Dwrite(t.handle.get(), memory_type, memory.get(), space.get(), H5P_DEFAULT, data) < 0) {
      blobs_detail::throw_hdf5_write_failure(where + ": cannot write the row");
    }
  }
  auto g = group_index.find(group);
  if (g == group_index.end()) {
    g = group_index.emplace(group, static_cast<std::int64_t>(groups.size())).first;
    groups.push_back(group);
  }
  t.index.push_back(g->second);
  t.index.push_back(static_cast<std::int64_t>(count));
  t.rows += 1;
  t.width = width;
  names.emplace(name);
}

// The group names and each table's row index (small: written uncompressed, contiguous).
void SegmentWriter::Impl::write_index() {
  const std::string where = path.string() + ": index";
  Hid links(H5Pcreate(H5P_LINK_CREATE));
  if (!links.valid() || H5Pset_create_intermediate_group(links.get(), 1) < 0)
    blobs_detail::throw_hdf5_write_failure(where + ": cannot set up");
  auto put = [&](const std::string& dataset, hid_t file_type, hid_t memory_type, int rank,
                 const hsize_t* dims, const void* data) {
    Hid space(H5Screate_simple(rank, dims, nullptr));
    Hid d(H5Dcreate2(file.get(), dataset.c_str(), file_type, space.get(), links.get(), H5P_DEFAULT,
                     H5P_DEFAULT));
    bool empty = false;
    for (int r = 0; r < rank; ++r) empty = empty || dims[r] == 0;
    if (!d.valid() ||
        (!empty && H5Dwrite(d.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) ||
        !d.reset())
      blobs_detail::throw_hdf5_write_failure(where + ": cannot write " + dataset);
  };
  std::string text;
  for (const std::string& g : groups) text += g + '\n';
  const hsize_t text_size[1] = {text.size()};
  put(blobs_detail::kGroupsDataset, H5T_STD_U8LE, H5T_NATIVE_UCHAR, 1, text_size, text.data());
  for (auto& [key, t] : tables) {
    const hsize_t dims[2] = {t.rows, 2};
    put(std::string(blobs_detail::kIndexGroup) + "/" + t.dataset, H5T_STD_I64LE, H5T_NATIVE_INT64,
        2, dims, t.index.data());
    if (!t.handle.reset())
      blobs_detail::throw_hdf5_write_failure(path.string() + ": cannot close the dataset '" +
                                             t.dataset + "'");
  }
}

SegmentWriter::SegmentWriter(const std::filesystem::path& blobs_dir, SegmentId id,
                             const SegmentProvenance& provenance, SegmentWriterOptions options)
    : impl_(std::make_unique<Impl>()) {
  if (!id.valid()) throw std::invalid_argument("SegmentWriter: invalid segment id");
  if (options.zstd_level < 1 || options.zstd_level > 22 || options.chunk_elements == 0) {
    throw std::invalid_argument("SegmentWriter: zstd level must be 1..22, chunk size > 0");
  }
  register_zstd_filter();
  impl_->blobs_dir = blobs_dir;
  impl_->path = blobs_dir / segment_file_name(id);
  impl_->id = id;
  impl_->options = options;

  std::error_code ec;
  std::filesystem::create_directories(blobs_dir, ec);
  if (ec)
    throw EnvironmentError(blobs_dir.string() +
                           ": cannot create the blobs directory: " + ec.message());

  QuietErrors quiet;
  if (std::filesystem::exists(impl_->path)) {
    throw InputError(impl_->path.string() + ": segment already exists; segments are written once");
  }
  impl_->file = Hid(H5Fcreate(impl_->path.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT));
  if (!impl_->file.valid()) {
    // It may exist, empty or partly written (a full disk): created here (exclusively), so
    // ours, unless the exclusive create found another writer's file.
    const blobs_detail::Hdf5Failure failure = blobs_detail::take_hdf5_failure();
    if (failure.os_errno != EEXIST) std::filesystem::remove(impl_->path, ec);
    throw EnvironmentError(impl_->path.string() + ": cannot create HDF5 segment" +
                           blobs_detail::failure_text(failure));
  }
  const std::string version =
      provenance.writer_version.empty() ? version_string() : provenance.writer_version;
  const hid_t f = impl_->file.get();
  if (!blobs_detail::write_int_attribute(f, "hapstate_segment_format", kSegmentFormatVersion) ||
      !blobs_detail::write_int_attribute(f, "hapstate_segment_id", id.value) ||
      !blobs_detail::write_string_attribute(f, "hapstate_writer_version", version) ||
      !blobs_detail::write_string_attribute(f, "hapstate_scene_hash", provenance.scene_hash) ||
      !blobs_detail::write_string_attribute(f, "hapstate_stage", provenance.stage)) {
    const blobs_detail::Hdf5Failure failure = blobs_detail::take_hdf5_failure();
    impl_->file.reset();
    take_hdf5_error();
    std::filesystem::remove(impl_->path, ec);
    throw EnvironmentError(impl_->path.string() + ": cannot write provenance" +
                           blobs_detail::failure_text(failure));
  }
}

SegmentWriter::~SegmentWriter() {
  if (!impl_ || impl_->closed) return;
  QuietErrors quiet;
  impl_->tables.clear();  // their datasets before the file
  impl_->file.reset();
  take_hdf5_error();
  std::error_code ec;
  std::filesystem::remove(impl_->path, ec);  // abandoned: never referenced, so just garbage
}

SegmentWriter::SegmentWriter(SegmentWriter&&) noexcept = default;
SegmentWriter& SegmentWriter::operator=(SegmentWriter&&) noexcept = default;

void SegmentWriter::write(std::string_view name, std::span<const double> values,
                          Precision precision) {
  const hid_t file_type = precision == Precision::kFloat32 ? H5T_IEEE_F32LE : H5T_IEEE_F64LE;
  impl_->write_row(name, values.data(), values.size(), file_type, H5T_NATIVE_DOUBLE);
}

void SegmentWriter::write(std::string_view name, std::span<const float> values) {
  impl_->write_row(name, values.data(), values.size(), H5T_IEEE_F32LE, H5T_NATIVE_FLOAT);
}

void SegmentWriter::write(std::string_view name, std::span<const int> values) {
  impl_->write_row(name, values.data(), values.size(), H5T_STD_I32LE, H5T_NATIVE_INT);
}

void SegmentWriter::close() {
  if (impl_->closed) return;
  QuietErrors quiet;
  const std::string where = impl_->path.string();
  const hid_t f = impl_->file.get();
  impl_->write_index();
  if (!blobs_detail::write_int_attribute(f, "hapstate_vector_count",
                                         static_cast<long long>(impl_->names.size())) ||
      !blobs_detail::write_int_attribute(f, "hapstate_complete", 1) ||
      H5Fflush(f, H5F_SCOPE_LOCAL) < 0) {
    blobs_detail::throw_hdf5_write_failure(where + ": cannot flush the segment");
  }
  if (!impl_->file.reset())
    blobs_detail::throw_hdf5_write_failure(where + ": cannot close the segment");
  impl_->closed = true;  // from here on the file is complete; a failed fsync leaves it as garbage
  sync_path(impl_->path, false);
  sync_path(impl_->blobs_dir, true);
}

SegmentId SegmentWriter::id() const { return impl_->id; }
const std::filesystem::path& SegmentWriter::path() const { return impl_->path; }
std::size_t SegmentWriter::num_vectors() const { return impl_->names.size(); }

}  // namespace hapstate
