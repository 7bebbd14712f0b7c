#include "blobs/blob_store.h"

#include "blobs/hdf5_support.hpp"
#include "blobs/zstd_filter.h"
#include "util/error.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <list>
#include <mutex>
#include <string>

namespace hapstate {

using blobs_detail::Hid;
using blobs_detail::QuietErrors;
using blobs_detail::take_hdf5_error;

namespace {

std::string with_reason(std::string message) {
  const std::string reason = take_hdf5_error();
  if (!reason.empty()) message += " (HDF5: " + reason + ")";
  return message;
}

std::string vector_place(const std::filesystem::path& file, std::string_view name) {
  return file.string() + ": vector '" + std::string(name) + "'";
}

}  // namespace

struct BlobStore::Impl {
  std::filesystem::path dir;
  std::size_t max_open = 32;
  mutable std::mutex mutex;
  struct Entry {
    SegmentId id;
    std::shared_ptr<Hid> file;
  };
  mutable std::list<Entry> cache;  // most recently used first

  std::filesystem::path path_of(SegmentId id) const { return dir / segment_file_name(id); }
  std::shared_ptr<Hid> open(SegmentId id) const;
  Hid open_dataset(SegmentId id, std::string_view name, std::shared_ptr<Hid>* file_out,
                   bool missing_ok) const;
  template <class T>
  std::vector<T> read(SegmentId id, std::string_view name, hid_t memory_type) const;
};

std::shared_ptr<Hid> BlobStore::Impl::open(SegmentId id) const {
  if (!id.valid()) {
    throw InputError(dir.string() + ": invalid segment id " + std::to_string(id.value));
  }
  std::lock_guard lock(mutex);
  for (auto it = cache.begin(); it != cache.end(); ++it) {
    if (it->id == id) {
      cache.splice(cache.begin(), cache, it);
      return cache.front().file;
    }
  }
  const std::filesystem::path path = path_of(id);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path.string() + ": segment file is missing (" + ec.message() + ")");
  QuietErrors quiet;
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    take_hdf5_error();
    throw InputError(path.string() + ": not an HDF5 file (" + std::to_string(bytes) +
                     " bytes; corrupt or truncated segment)");
  }
  auto file = std::make_shared<Hid>(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file->valid()) {
    throw InputError(with_reason(path.string() + ": truncated or corrupt segment, cannot open it (" +
                                 std::to_string(bytes) + " bytes)"));
  }
  const auto format = blobs_detail::read_int_attribute(file->get(), "hapstate_segment_format");
  if (!format) {
    throw InputError(path.string() + ": not a hapstate segment (no hapstate_segment_format attribute)");
  }
  if (*format > kSegmentFormatVersion) {
    throw InputError(path.string() + ": segment format " + std::to_string(*format) +
                     ", this hapstate reads up to " + std::to_string(kSegmentFormatVersion) +
                     ": upgrade hapstate");
  }
  if (blobs_detail::read_int_attribute(file->get(), "hapstate_complete").value_or(0) != 1) {
    throw InputError(path.string() +
                     ": incomplete segment (its writer never closed it: crash during a write?)");
  }
  take_hdf5_error();
  cache.push_front({id, file});
  while (cache.size() > max_open) cache.pop_back();  // readers still holding it keep it open
  return file;
}

Hid BlobStore::Impl::open_dataset(SegmentId id, std::string_view name,
                                  std::shared_ptr<Hid>* file_out, bool missing_ok) const {
  std::shared_ptr<Hid> file = open(id);
  const std::filesystem::path path = path_of(id);
  if (!is_valid_vector_name(name)) throw InputError(vector_place(path, name) + ": invalid name");
  QuietErrors quiet;
  const std::string full(name);
  for (std::size_t slash = 0; slash != std::string::npos;) {
    slash = full.find('/', slash + 1);
    const std::string prefix = full.substr(0, slash);
    if (H5Lexists(file->get(), prefix.c_str(), H5P_DEFAULT) <= 0) {
      take_hdf5_error();
      if (missing_ok) return Hid();
      throw InputError(vector_place(path, name) + ": no such dataset in this segment");
    }
  }
  Hid dataset(H5Dopen2(file->get(), full.c_str(), H5P_DEFAULT));
  if (!dataset.valid()) {
    throw InputError(with_reason(vector_place(path, name) + ": cannot open the dataset (corrupt?)"));
  }
  *file_out = std::move(file);
  return dataset;
}

template <class T>
std::vector<T> BlobStore::Impl::read(SegmentId id, std::string_view name, hid_t memory_type) const {
  std::shared_ptr<Hid> file;
  Hid dataset = open_dataset(id, name, &file, false);
  const std::string where = vector_place(path_of(id), name);
  QuietErrors quiet;
  Hid space(H5Dget_space(dataset.get()));
  Hid type(H5Dget_type(dataset.get()));
  if (!space.valid() || !type.valid() || H5Sget_simple_extent_ndims(space.get()) != 1 ||
      H5Tget_class(type.get()) != H5T_FLOAT) {
    throw InputError(with_reason(where + ": not a 1-D floating-point dataset"));
  }
  hsize_t count = 0;
  H5Sget_simple_extent_dims(space.get(), &count, nullptr);
  std::vector<T> values(static_cast<std::size_t>(count));
  if (count > 0 &&
      H5Dread(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
    throw InputError(with_reason(where + ": cannot read the data (corrupt chunk?)"));
  }
  return values;
}

BlobStore::BlobStore(std::filesystem::path blobs_dir, std::size_t max_open_files)
    : impl_(std::make_unique<Impl>()) {
  register_zstd_filter();
  impl_->dir = std::move(blobs_dir);
  impl_->max_open = std::max<std::size_t>(max_open_files, 1);
}

BlobStore::~BlobStore() {
  if (impl_) close_all();
}

const std::filesystem::path& BlobStore::directory() const { return impl_->dir; }

std::vector<double> BlobStore::read(SegmentId id, std::string_view name) const {
  return impl_->read<double>(id, name, H5T_NATIVE_DOUBLE);
}

std::vector<float> BlobStore::read_float32(SegmentId id, std::string_view name) const {
  return impl_->read<float>(id, name, H5T_NATIVE_FLOAT);
}

bool BlobStore::contains(SegmentId id, std::string_view name) const {
  std::shared_ptr<Hid> file;
  return impl_->open_dataset(id, name, &file, true).valid();
}

std::size_t BlobStore::size_of(SegmentId id, std::string_view name) const {
  std::shared_ptr<Hid> file;
  Hid dataset = impl_->open_dataset(id, name, &file, false);
  QuietErrors quiet;
  Hid space(H5Dget_space(dataset.get()));
  hsize_t count = 0;
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 1 ||
      H5Sget_simple_extent_dims(space.get(), &count, nullptr) < 0) {
    throw InputError(with_reason(vector_place(impl_->path_of(id), name) + ": not a 1-D dataset"));
  }
  return static_cast<std::size_t>(count);
}

namespace {

herr_t collect_dataset(hid_t, const char* name, const H5O_info_t* info, void* out) {
  if (info->type == H5O_TYPE_DATASET) static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

}  // namespace

std::vector<std::string> BlobStore::list_vectors(SegmentId id) const {
  std::shared_ptr<Hid> file = impl_->open(id);
  QuietErrors quiet;
  std::vector<std::string> names;
  if (H5Ovisit2(file->get(), H5_INDEX_NAME, H5_ITER_INC, collect_dataset, &names, H5O_INFO_BASIC) < 0) {
    throw InputError(with_reason(impl_->path_of(id).string() + ": cannot list the vectors (corrupt?)"));
  }
  std::sort(names.begin(), names.end());
  return names;
}

Precision BlobStore::precision_of(SegmentId id, std::string_view name) const {
  std::shared_ptr<Hid> file;
  Hid dataset = impl_->open_dataset(id, name, &file, false);
  QuietErrors quiet;
  Hid type(H5Dget_type(dataset.get()));
  if (!type.valid() || H5Tget_class(type.get()) != H5T_FLOAT) {
    throw InputError(with_reason(vector_place(impl_->path_of(id), name) +
                                 ": not a floating-point dataset"));
  }
  return H5Tget_size(type.get()) <= 4 ? Precision::kFloat32 : Precision::kFloat64;
}

SegmentProvenance BlobStore::provenance(SegmentId id) const {
  std::shared_ptr<Hid> file = impl_->open(id);
  QuietErrors quiet;
  SegmentProvenance p;
  p.scene_hash = blobs_detail::read_string_attribute(file->get(), "hapstate_scene_hash").value_or("");
  p.writer_version =
      blobs_detail::read_string_attribute(file->get(), "hapstate_writer_version").value_or("");
  p.stage = blobs_detail::read_string_attribute(file->get(), "hapstate_stage").value_or("");
  take_hdf5_error();
  return p;
}

std::vector<SegmentId> BlobStore::list_segments() const {
  std::vector<SegmentId> ids;
  std::error_code ec;
  if (!std::filesystem::exists(impl_->dir, ec)) return ids;
  for (const auto& entry : std::filesystem::directory_iterator(impl_->dir, ec)) {
    if (!entry.is_regular_file()) continue;
    if (auto id = parse_segment_file_name(entry.path().filename().string())) ids.push_back(*id);
  }
  if (ec) throw EnvironmentError(impl_->dir.string() + ": cannot list the blobs directory: " + ec.message());
  std::sort(ids.begin(), ids.end());
  return ids;
}

SegmentId BlobStore::next_segment_id() const {
  const auto ids = list_segments();
  return ids.empty() ? SegmentId{1} : SegmentId{ids.back().value + 1};
}

std::vector<std::filesystem::path> BlobStore::unreferenced_segments(
    const std::set<SegmentId>& referenced) const {
  std::vector<std::filesystem::path> garbage;
  for (SegmentId id : list_segments()) {
    if (!referenced.contains(id)) garbage.push_back(impl_->path_of(id));
  }
  return garbage;
}

std::vector<std::filesystem::path> BlobStore::remove_unreferenced_segments(
    const std::set<SegmentId>& referenced) {
  const auto garbage = unreferenced_segments(referenced);
  if (garbage.empty()) return garbage;
  {
    std::lock_guard lock(impl_->mutex);
    impl_->cache.remove_if([&](const Impl::Entry& e) { return !referenced.contains(e.id); });
  }
  for (const auto& path : garbage) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    if (ec) throw EnvironmentError(path.string() + ": cannot remove unreferenced segment: " + ec.message());
  }
  const int fd = ::open(impl_->dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  return garbage;
}

void BlobStore::close_all() const {
  std::lock_guard lock(impl_->mutex);
  QuietErrors quiet;
  impl_->cache.clear();
  take_hdf5_error();
}

}  // namespace hapstate
