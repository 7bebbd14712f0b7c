#include "blobs/segment_writer.h"

#include "blobs/hdf5_support.hpp"
#include "blobs/zstd_filter.h"
#include "util/error.h"
#include "util/version.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>

namespace hapstate {

using blobs_detail::Hid;
using blobs_detail::QuietErrors;
using blobs_detail::take_hdf5_error;

namespace {

// fsync of a file or a directory by name; throws EnvironmentError naming it on failure.
void sync_path(const std::filesystem::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) {
    throw EnvironmentError(path.string() + ": cannot open for fsync: " + std::strerror(errno));
  }
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0) throw EnvironmentError(path.string() + ": fsync failed: " + std::strerror(err));
}

std::string with_reason(std::string message) {
  const std::string reason = take_hdf5_error();
  if (!reason.empty()) message += " (HDF5: " + reason + ")";
  return message;
}

}  // namespace

struct SegmentWriter::Impl {
  std::filesystem::path blobs_dir;
  std::filesystem::path path;
  SegmentId id;
  SegmentWriterOptions options;
  Hid file;
  std::set<std::string, std::less<>> names;
  bool closed = false;

  void write_dataset(std::string_view name, const void* data, std::size_t count, hid_t file_type,
                     hid_t memory_type);
};

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
  if (ec) throw EnvironmentError(blobs_dir.string() + ": cannot create the blobs directory: " + ec.message());

  QuietErrors quiet;
  if (std::filesystem::exists(impl_->path)) {
    throw InputError(impl_->path.string() + ": segment already exists; segments are written once");
  }
  impl_->file = Hid(H5Fcreate(impl_->path.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT));
  if (!impl_->file.valid()) {
    throw EnvironmentError(with_reason(impl_->path.string() + ": cannot create HDF5 segment"));
  }
  const std::string version =
      provenance.writer_version.empty() ? version_string() : provenance.writer_version;
  const hid_t f = impl_->file.get();
  if (!blobs_detail::write_int_attribute(f, "hapstate_segment_format", kSegmentFormatVersion) ||
      !blobs_detail::write_int_attribute(f, "hapstate_segment_id", id.value) ||
      !blobs_detail::write_string_attribute(f, "hapstate_writer_version", version) ||
      !blobs_detail::write_string_attribute(f, "hapstate_scene_hash", provenance.scene_hash) ||
      !blobs_detail::write_string_attribute(f, "hapstate_stage", provenance.stage)) {
    const std::string message = with_reason(impl_->path.string() + ": cannot write provenance");
    impl_->file.reset();
    std::filesystem::remove(impl_->path, ec);
    throw EnvironmentError(message);
  }
}

SegmentWriter::~SegmentWriter() {
  if (!impl_ || impl_->closed) return;
  QuietErrors quiet;
  impl_->file.reset();
  take_hdf5_error();
  std::error_code ec;
  std::filesystem::remove(impl_->path, ec);  // abandoned: never referenced, so just garbage
}

SegmentWriter::SegmentWriter(SegmentWriter&&) noexcept = default;
SegmentWriter& SegmentWriter::operator=(SegmentWriter&&) noexcept = default;

void SegmentWriter::Impl::write_dataset(std::string_view name, const void* data, std::size_t count,
                                        hid_t file_type, hid_t memory_type) {
  if (closed) throw std::logic_error("SegmentWriter::write after close()");
  const std::string where = path.string() + ": vector '" + std::string(name) + "'";
  if (!is_valid_vector_name(name)) {
    throw InputError(where + ": invalid name (parts of [A-Za-z0-9_.-] separated by '/')");
  }
  if (names.contains(name)) throw InputError(where + ": written twice");

  QuietErrors quiet;
  const hsize_t dims[1] = {static_cast<hsize_t>(count)};
  Hid space(H5Screate_simple(1, dims, nullptr));
  Hid create(H5Pcreate(H5P_DATASET_CREATE));
  Hid links(H5Pcreate(H5P_LINK_CREATE));
  bool ok = space.valid() && create.valid() && links.valid() &&
            H5Pset_create_intermediate_group(links.get(), 1) >= 0;
  if (ok && count > 0) {  // a chunk may not be longer than a fixed-size dataset; empty: contiguous
    const hsize_t chunk[1] = {static_cast<hsize_t>(std::min(count, options.chunk_elements))};
    const unsigned level = static_cast<unsigned>(options.zstd_level);
    ok = H5Pset_chunk(create.get(), 1, chunk) >= 0 && H5Pset_shuffle(create.get()) >= 0 &&
         H5Pset_filter(create.get(), static_cast<H5Z_filter_t>(kZstdFilterId), H5Z_FLAG_MANDATORY,
                       1, &level) >= 0;
  }
  if (!ok) throw InputError(with_reason(where + ": cannot set up the dataset"));
  const std::string hdf5_name(name);
  Hid dataset(H5Dcreate2(file.get(), hdf5_name.c_str(), file_type, space.get(), links.get(),
                         create.get(), H5P_DEFAULT));
  if (!dataset.valid()) throw EnvironmentError(with_reason(where + ": cannot create the dataset"));
  if (count > 0 && H5Dwrite(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
    throw EnvironmentError(with_reason(where + ": cannot write the dataset"));
  }
  if (!dataset.reset()) throw EnvironmentError(with_reason(where + ": cannot close the dataset"));
  names.emplace(name);
}

void SegmentWriter::write(std::string_view name, std::span<const double> values,
                          Precision precision) {
  const hid_t file_type = precision == Precision::kFloat32 ? H5T_IEEE_F32LE : H5T_IEEE_F64LE;
  impl_->write_dataset(name, values.data(), values.size(), file_type, H5T_NATIVE_DOUBLE);
}

void SegmentWriter::write(std::string_view name, std::span<const float> values) {
  impl_->write_dataset(name, values.data(), values.size(), H5T_IEEE_F32LE, H5T_NATIVE_FLOAT);
}

void SegmentWriter::close() {
  if (impl_->closed) return;
  QuietErrors quiet;
  const std::string where = impl_->path.string();
  const hid_t f = impl_->file.get();
  if (!blobs_detail::write_int_attribute(f, "hapstate_vector_count",
                                         static_cast<long long>(impl_->names.size())) ||
      !blobs_detail::write_int_attribute(f, "hapstate_complete", 1) ||
      H5Fflush(f, H5F_SCOPE_LOCAL) < 0) {
    throw EnvironmentError(with_reason(where + ": cannot flush the segment"));
  }
  if (!impl_->file.reset()) throw EnvironmentError(with_reason(where + ": cannot close the segment"));
  impl_->closed = true;  // from here on the file is complete; a failed fsync leaves it as garbage
  sync_path(impl_->path, false);
  sync_path(impl_->blobs_dir, true);
}

SegmentId SegmentWriter::id() const { return impl_->id; }
const std::filesystem::path& SegmentWriter::path() const { return impl_->path; }
std::size_t SegmentWriter::num_vectors() const { return impl_->names.size(); }

}  // namespace hapstate
