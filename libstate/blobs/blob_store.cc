#include "blobs/blob_store.h"

#include "blobs/hdf5_support.hpp"
#include "blobs/packed_layout.hpp"
#include "blobs/zstd_filter.h"
#include "util/error.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <list>
#include <map>
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

// Where each vector of a format-2 segment is: its table (2-D dataset), row and length.
struct Place {
  std::string table;
  hsize_t row = 0;
  hsize_t length = 0;
};
using Directory = std::map<std::string, Place, std::less<>>;

// An open segment: its file and, for format 2, the directory read from its index.
struct OpenSegment {
  Hid file;
  std::shared_ptr<const Directory> directory;  // nullptr: format 1 (a dataset per vector)
};

struct BlobStore::Impl {
  std::filesystem::path dir;
  std::size_t max_open = 32;
  mutable std::mutex mutex;
  struct Entry {
    SegmentId id;
    std::shared_ptr<OpenSegment> segment;
  };
  mutable std::list<Entry> cache;  // most recently used first

  std::filesystem::path path_of(SegmentId id) const { return dir / segment_file_name(id); }
  std::shared_ptr<OpenSegment> open(SegmentId id) const;
  // The dataset holding vector `name` and, for format 2, its row (place); an invalid Hid if it
  // is missing and missing_ok.
  Hid open_dataset(SegmentId id, std::string_view name, std::shared_ptr<OpenSegment>* segment_out,
                   const Place** place, bool missing_ok) const;
  template <class T>
  std::vector<T> read(SegmentId id, std::string_view name, hid_t memory_type) const;
};

namespace {

herr_t collect_link(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

// The directory of a format-2 segment from its index; throws InputError naming the file.
std::shared_ptr<const Directory> read_directory(hid_t file, const std::filesystem::path& path) {
  auto bad = [&](const std::string& what) -> InputError {
    return InputError(with_reason(path.string() + ": damaged segment index: " + what));
  };
  auto read_all = [&](const std::string& name, hid_t memory_type, int rank,
                      std::vector<hsize_t>* dims, auto* values) {
    Hid d(H5Dopen2(file, name.c_str(), H5P_DEFAULT));
    Hid space(d.valid() ? H5Dget_space(d.get()) : H5I_INVALID_HID);
    dims->assign(static_cast<std::size_t>(rank), 0);
    if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != rank ||
        H5Sget_simple_extent_dims(space.get(), dims->data(), nullptr) < 0)
      throw bad("'" + name + "' missing or of the wrong shape");
    hsize_t n = 1;
    for (hsize_t k : *dims) n *= k;
    values->resize(static_cast<std::size_t>(n));
    if (n > 0 && H5Dread(d.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values->data()) < 0)
      blobs_detail::throw_hdf5_read_failure(path.string(), "cannot read the index '" + name + "'",
                                            "damaged segment index: '" + name + "' unreadable");
  };
  std::vector<hsize_t> dims;
  std::string text;
  read_all(blobs_detail::kGroupsDataset, H5T_NATIVE_CHAR, 1, &dims, &text);
  std::vector<std::string> groups;
  for (std::size_t start = 0; start < text.size();) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) throw bad("group names do not end with a newline");
    groups.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  std::vector<std::string> tables;
  Hid index(H5Gopen2(file, blobs_detail::kIndexGroup, H5P_DEFAULT));
  if (!index.valid() ||
      H5Literate(index.get(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_link, &tables) < 0)
    throw bad("cannot list the tables");
  auto directory = std::make_shared<Directory>();
  for (const std::string& table : tables) {
    if (table == "groups") continue;
    std::vector<std::int64_t> rows;
    read_all(std::string(blobs_detail::kIndexGroup) + "/" + table, H5T_NATIVE_INT64, 2, &dims,
             &rows);
    if (dims[1] != 2) throw bad("the index of '" + table + "' is not [rows x 2]");
    Hid data(H5Dopen2(file, table.c_str(), H5P_DEFAULT));
    Hid space(data.valid() ? H5Dget_space(data.get()) : H5I_INVALID_HID);
    hsize_t extent[2] = {0, 0};
    if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 2 ||
        H5Sget_simple_extent_dims(space.get(), extent, nullptr) < 0 || extent[0] != dims[0])
      throw bad("table '" + table + "' is missing or has not the rows its index lists");
    // Its leaf name (a table of a second storage type of a leaf has a suffix).
    const std::string leaf =
        blobs_detail::read_string_attribute(data.get(), "hapstate_leaf").value_or(table);
    for (hsize_t r = 0; r < dims[0]; ++r) {
      const std::int64_t group = rows[2 * r], length = rows[2 * r + 1];
      if (group < 0 || group >= static_cast<std::int64_t>(groups.size()) || length < 0 ||
          static_cast<hsize_t>(length) > extent[1])
        throw bad("row " + std::to_string(r) + " of '" + table + "' is out of range");
      const std::string& g = groups[static_cast<std::size_t>(group)];
      const std::string name = g.empty() ? leaf : std::string(g).append("/").append(leaf);
      if (!directory->emplace(name, Place{table, r, static_cast<hsize_t>(length)}).second)
        throw bad("vector '" + name + "' listed twice");
    }
  }
  return directory;
}

}  // namespace

std::shared_ptr<OpenSegment> BlobStore::Impl::open(SegmentId id) const {
  if (!id.valid()) {
    throw InputError(dir.string() + ": invalid segment id " + std::to_string(id.value));
  }
  std::lock_guard lock(mutex);
  for (auto it = cache.begin(); it != cache.end(); ++it) {
    if (it->id == id) {
      cache.splice(cache.begin(), cache, it);
      return cache.front().segment;
    }
  }
  const std::filesystem::path path = path_of(id);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(path.string() + ": segment file is missing (" + ec.message() + ")");
  QuietErrors quiet;
  // An OS error (permission, I/O error) is the environment's; anything else the file's.
  const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
  if (is_hdf5 < 0) {
    blobs_detail::throw_hdf5_read_failure(
        path.string(), "cannot read the segment",
        "not an HDF5 file (" + std::to_string(bytes) + " bytes; corrupt or truncated segment)");
  }
  if (is_hdf5 == 0) {
    take_hdf5_error();
    throw InputError(path.string() + ": not an HDF5 file (" + std::to_string(bytes) +
                     " bytes; corrupt or truncated segment)");
  }
  auto segment = std::make_shared<OpenSegment>();
  segment->file = Hid(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  const Hid* file = &segment->file;
  if (!file->valid()) {
    blobs_detail::throw_hdf5_read_failure(
        path.string(), "cannot open the segment",
        "truncated or corrupt segment, cannot open it (" + std::to_string(bytes) + " bytes)");
  }
  const auto format = blobs_detail::read_int_attribute(file->get(), "hapstate_segment_format");
  if (!format) {
    throw InputError(path.string() +
                     ": not a hapstate segment (no hapstate_segment_format attribute)");
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
  if (*format >= 2) segment->directory = read_directory(file->get(), path);
  take_hdf5_error();
  cache.push_front({id, segment});
  while (cache.size() > max_open) cache.pop_back();  // readers still holding it keep it open
  return segment;
}

Hid BlobStore::Impl::open_dataset(SegmentId id, std::string_view name,
                                  std::shared_ptr<OpenSegment>* segment_out, const Place** place,
                                  bool missing_ok) const {
  std::shared_ptr<OpenSegment> segment = open(id);
  const std::filesystem::path path = path_of(id);
  if (!is_valid_vector_name(name)) throw InputError(vector_place(path, name) + ": invalid name");
  QuietErrors quiet;
  std::string dataset_name(name);
  *place = nullptr;
  if (segment->directory) {
    const auto it = segment->directory->find(name);
    if (it == segment->directory->end()) {
      if (missing_ok) return Hid();
      throw InputError(vector_place(path, name) + ": no such vector in this segment");
    }
    *place = &it->second;
    dataset_name = it->second.table;
  } else {
    for (std::size_t slash = 0; slash != std::string::npos;) {
      slash = dataset_name.find('/', slash + 1);
      const std::string prefix = dataset_name.substr(0, slash);
      if (H5Lexists(segment->file.get(), prefix.c_str(), H5P_DEFAULT) <= 0) {
        take_hdf5_error();
        if (missing_ok) return Hid();
        throw InputError(vector_place(path, name) + ": no such dataset in this segment");
      }
    }
  }
  Hid dataset(H5Dopen2(segment->file.get(), dataset_name.c_str(), H5P_DEFAULT));
  if (!dataset.valid()) {
    throw InputError(
        with_reason(vector_place(path, name) + ": cannot open the dataset (corrupt?)"));
  }
  *segment_out = std::move(segment);
  return dataset;
}

template <class T>
std::vector<T> BlobStore::Impl::read(SegmentId id, std::string_view name, hid_t memory_type) const {
  std::shared_ptr<OpenSegment> segment;
  const Place* place = nullptr;
  Hid dataset = open_dataset(id, name, &segment, &place, false);
  const std::string where = vector_place(path_of(id), name);
  QuietErrors quiet;
  Hid space(H5Dget_space(dataset.get()));
  Hid type(H5Dget_type(dataset.get()));
  const int rank = place ? 2 : 1;
  const H5T_class_t type_class = type.valid() ? H5Tget_class(type.get()) : H5T_NO_CLASS;
  if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != rank ||
      (type_class != H5T_FLOAT && type_class != H5T_INTEGER)) {
    throw InputError(with_reason(where + ": not a " + std::to_string(rank) + "-D numeric dataset"));
  }
  hsize_t count = 0;
  Hid memory;
  if (place) {  // its row
    count = place->length;
    const hsize_t start[2] = {place->row, 0}, size[2] = {1, count};
    memory = Hid(H5Screate_simple(1, &count, nullptr));
    if (count > 0 &&
        H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start, nullptr, size, nullptr) < 0)
      throw InputError(with_reason(where + ": row outside the dataset"));
  } else {
    H5Sget_simple_extent_dims(space.get(), &count, nullptr);
  }
  std::vector<T> values(static_cast<std::size_t>(count));
  if (count > 0 && H5Dread(dataset.get(), memory_type, place ? memory.get() : H5S_ALL,
                           place ? space.get() : H5S_ALL, H5P_DEFAULT, values.data()) < 0) {
    blobs_detail::throw_hdf5_read_failure(where, "cannot read the data",
                                          "cannot read the data (corrupt chunk?)");
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
  std::shared_ptr<OpenSegment> segment = impl_->open(id);
  if (segment->directory) return is_valid_vector_name(name) && segment->directory->contains(name);
  const Place* place = nullptr;
  return impl_->open_dataset(id, name, &segment, &place, true).valid();
}

std::size_t BlobStore::size_of(SegmentId id, std::string_view name) const {
  std::shared_ptr<OpenSegment> segment;
  const Place* place = nullptr;
  Hid dataset = impl_->open_dataset(id, name, &segment, &place, false);
  if (place) return static_cast<std::size_t>(place->length);
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
  if (info->type == H5O_TYPE_DATASET)
    static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

}  // namespace

std::vector<std::string> BlobStore::list_vectors(SegmentId id) const {
  std::shared_ptr<OpenSegment> segment = impl_->open(id);
  std::vector<std::string> names;
  if (segment->directory) {
    for (const auto& [name, place] : *segment->directory) names.push_back(name);
    return names;  // sorted: the directory is a map
  }
  QuietErrors quiet;
  if (H5Ovisit2(segment->file.get(), H5_INDEX_NAME, H5_ITER_INC, collect_dataset, &names,
                H5O_INFO_BASIC) < 0) {
    throw InputError(
        with_reason(impl_->path_of(id).string() + ": cannot list the vectors (corrupt?)"));
  }
  std::sort(names.begin(), names.end());
  return names;
}

Precision BlobStore::precision_of(SegmentId id, std::string_view name) const {
  std::shared_ptr<OpenSegment> segment;
  const Place* place = nullptr;
  Hid dataset = impl_->open_dataset(id, name, &segment, &place, false);
  QuietErrors quiet;
  Hid type(H5Dget_type(dataset.get()));
  const H5T_class_t type_class = type.valid() ? H5Tget_class(type.get()) : H5T_NO_CLASS;
  if (type_class == H5T_INTEGER) return Precision::kInt32;
  if (type_class != H5T_FLOAT) {
    throw InputError(
        with_reason(vector_place(impl_->path_of(id), name) + ": not a numeric dataset"));
  }
  return H5Tget_size(type.get()) <= 4 ? Precision::kFloat32 : Precision::kFloat64;
}

SegmentProvenance BlobStore::provenance(SegmentId id) const {
  std::shared_ptr<OpenSegment> segment = impl_->open(id);
  const Hid* file = &segment->file;
  QuietErrors quiet;
  SegmentProvenance p;
  p.scene_hash =
      blobs_detail::read_string_attribute(file->get(), "hapstate_scene_hash").value_or("");
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
  if (ec)
    throw EnvironmentError(impl_->dir.string() +
                           ": cannot list the blobs directory: " + ec.message());
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
  auto garbage = unreferenced_segments(referenced);
  if (garbage.empty()) return garbage;
  {
    std::lock_guard lock(impl_->mutex);
    impl_->cache.remove_if([&](const Impl::Entry& e) { return !referenced.contains(e.id); });
  }
  for (const auto& path : garbage) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    if (ec)
      throw EnvironmentError(path.string() +
                             ": cannot remove unreferenced segment: " + ec.message());
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
