#include "blobs/hdf5_support.hpp"

#include "util/error.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace hapstate::blobs_detail {

bool Hid::reset() {
  if (id_ < 0) return true;
  const hid_t id = std::exchange(id_, H5I_INVALID_HID);
  return H5Idec_ref(id) >= 0;
}

QuietErrors::QuietErrors() {
  H5Eget_auto2(H5E_DEFAULT, &old_func_, &old_data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

QuietErrors::~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, old_func_, old_data_); }

namespace {
herr_t keep_innermost(unsigned /*n*/, const H5E_error2_t* err, void* data) {
  if (err->desc != nullptr && err->desc[0] != '\0') *static_cast<std::string*>(data) = err->desc;
  return 0;
}
}  // namespace

std::string take_hdf5_error() {
  std::string text;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, keep_innermost, &text);
  H5Eclear2(H5E_DEFAULT);
  return text;
}

namespace {

struct Walk {
  std::string innermost;
  std::string with_errno;  // the entry that named an errno
  int os_errno = 0;
};

// HDF5's file drivers format OS failures as "..., errno = <n>, error message = '<text>', ...".
herr_t find_errno(unsigned /*n*/, const H5E_error2_t* err, void* data) {
  auto* walk = static_cast<Walk*>(data);
  if (err->desc == nullptr || err->desc[0] == '\0') return 0;
  walk->innermost = err->desc;
  if (const char* at = std::strstr(err->desc, "errno = "); at != nullptr) {
    char* end = nullptr;
    const long value = std::strtol(at + 8, &end, 10);
    if (end != at + 8 && value > 0 && value < 4096) {
      walk->os_errno = static_cast<int>(value);
      walk->with_errno = err->desc;
    }
  }
  return 0;
}

}  // namespace

Hdf5Failure take_hdf5_failure() {
  Walk walk;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, find_errno, &walk);
  H5Eclear2(H5E_DEFAULT);
  Hdf5Failure f;
  f.os_errno = walk.os_errno;
  if (walk.os_errno != 0) {
    // "file write failed: time = ..., filename = ..., errno = 28, ...": the words before the
    // first ':' (the rest repeats the file name, the time and buffer addresses).
    f.reason = walk.with_errno.substr(0, walk.with_errno.find(':'));
  } else {
    f.reason = walk.innermost;
  }
  return f;
}

bool is_environment_errno(int os_errno) {
  switch (os_errno) {
    case ENOSPC:
    case EDQUOT:
    case EFBIG:
    case EIO:
    case EACCES:
    case EPERM:
    case EROFS:
    case EMFILE:
    case ENFILE:
    case ENOMEM:
    case EBUSY:
    case ENXIO:
    case ENODEV:
    case ESTALE:
    case ETIMEDOUT:
    case EAGAIN:  // EAGAIN: HDF5's file lock held by another process
      return true;
    default:
      return false;
  }
}

namespace {

std::string hdf5_suffix(const Hdf5Failure& f) {
  return f.reason.empty() ? std::string() : " (HDF5: " + f.reason + ")";
}

}  // namespace

std::string failure_text(const Hdf5Failure& f) {
  return (f.os_errno != 0 ? std::string(": ") + os_error_text(f.os_errno) : std::string()) +
         hdf5_suffix(f);
}

void throw_hdf5_write_failure(const std::string& where) {
  throw EnvironmentError(where + failure_text(take_hdf5_failure()));
}

void throw_hdf5_read_failure(const std::string& where, const std::string& action,
                             const std::string& corrupt) {
  const Hdf5Failure f = take_hdf5_failure();
  if (is_environment_errno(f.os_errno))
    throw EnvironmentError(where + ": " + action + ": " + os_error_text(f.os_errno) +
                           hdf5_suffix(f));
  throw InputError(where + ": " + corrupt + hdf5_suffix(f));
}

bool write_string_attribute(hid_t object, const char* name, const std::string& value) {
  Hid type(H5Tcopy(H5T_C_S1));
  if (!type.valid() || H5Tset_size(type.get(), value.size() + 1) < 0 ||
      H5Tset_strpad(type.get(), H5T_STR_NULLTERM) < 0) {
    return false;
  }
  Hid space(H5Screate(H5S_SCALAR));
  Hid attr(H5Acreate2(object, name, type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!attr.valid()) return false;
  return H5Awrite(attr.get(), type.get(), value.c_str()) >= 0 && attr.reset();
}

bool write_int_attribute(hid_t object, const char* name, long long value) {
  Hid space(H5Screate(H5S_SCALAR));
  Hid attr(H5Acreate2(object, name, H5T_STD_I64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!attr.valid()) return false;
  return H5Awrite(attr.get(), H5T_NATIVE_LLONG, &value) >= 0 && attr.reset();
}

std::optional<std::string> read_string_attribute(hid_t object, const char* name) {
  if (H5Aexists(object, name) <= 0) return std::nullopt;
  Hid attr(H5Aopen(object, name, H5P_DEFAULT));
  Hid type(attr.valid() ? H5Aget_type(attr.get()) : H5I_INVALID_HID);
  if (!type.valid() || H5Tget_class(type.get()) != H5T_STRING ||
      H5Tis_variable_str(type.get()) != 0) {
    return std::nullopt;
  }
  const size_t size = H5Tget_size(type.get());
  std::string value(size, '\0');
  Hid mem(H5Tcopy(type.get()));
  if (H5Aread(attr.get(), mem.get(), value.data()) < 0) return std::nullopt;
  value.resize(value.find('\0') == std::string::npos ? size : value.find('\0'));
  return value;
}

std::optional<long long> read_int_attribute(hid_t object, const char* name) {
  if (H5Aexists(object, name) <= 0) return std::nullopt;
  Hid attr(H5Aopen(object, name, H5P_DEFAULT));
  Hid type(attr.valid() ? H5Aget_type(attr.get()) : H5I_INVALID_HID);
  if (!type.valid() || H5Tget_class(type.get()) != H5T_INTEGER) return std::nullopt;
  long long value = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_LLONG, &value) < 0) return std::nullopt;
  return value;
}

}  // namespace hapstate::blobs_detail
