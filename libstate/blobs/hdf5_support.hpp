// PRIVATE to the blobs module (named .hpp so it is not installed with the public *.h headers:
// it exposes the HDF5 C API). RAII handles, a guard that keeps HDF5's error stack off stderr,
// and the text of the innermost HDF5 error for our own messages.
#pragma once

#include <hdf5.h>

#include <optional>
#include <string>
#include <utility>

namespace hapstate::blobs_detail {

// Owns one HDF5 identifier (file, group, dataset, dataspace, property list, type, attribute)
// and closes it with H5Idec_ref. Move-only. A negative id means "none".
class Hid {
 public:
  Hid() = default;
  explicit Hid(hid_t id) : id_(id) {}
  Hid(Hid&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Hid& operator=(Hid&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Hid(const Hid&) = delete;
  Hid& operator=(const Hid&) = delete;
  ~Hid() { reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Closes now; returns false if HDF5 reported an error while closing (e.g. a failed flush).
  bool reset();

 private:
  hid_t id_ = H5I_INVALID_HID;
};

// While alive, HDF5 errors on this thread are not printed (H5Eset_auto is off); the previous
// handler is restored on destruction. Every blobs entry point holds one, so a failing
// H5Fopen in our code never writes HDF5's error stack to stderr.
class QuietErrors {
 public:
  QuietErrors();
  ~QuietErrors();
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;

 private:
  H5E_auto2_t old_func_ = nullptr;
  void* old_data_ = nullptr;
};

// The innermost (most specific) message on this thread's HDF5 error stack, e.g.
// "truncated file: eof = 4096, sblock->base_addr = 0, stored_eof = 8192"; clears the stack.
// Empty if the stack is empty.
std::string take_hdf5_error();

// What HDF5's error stack on this thread says about the last failure (and clears it): the
// innermost message and the OS errno a file driver recorded, e.g. the sec2 driver's
// "file write failed: time = ..., errno = 28, error message = 'No space left on device', ..."
// gives os_errno 28 and reason "file write failed". os_errno is 0 if no entry names one.
struct Hdf5Failure {
  std::string reason;
  int os_errno = 0;
};
Hdf5Failure take_hdf5_failure();
// ": <strerror(os_errno)> (HDF5: <reason>)", each part only if known.
std::string failure_text(const Hdf5Failure& failure);

// Whether an OS error says the environment failed rather than the file's content: no space
// (ENOSPC, EDQUOT, EFBIG), an I/O error (EIO), a permission (EACCES, EPERM), a read-only file
// system (EROFS), too many open files, no memory, a busy or vanished device.
bool is_environment_errno(int os_errno);

// Throws for a writer's HDF5 call that failed at `where` (the file, and the place in it),
// consuming HDF5's error stack: EnvironmentError "<where>: <strerror(errno)> (HDF5: <reason>)",
// or "<where> (HDF5: <reason>)" if HDF5 recorded no OS error (a writer creates its file, so
// its content cannot be the user's fault).
[[noreturn]] void throw_hdf5_write_failure(const std::string& where);

// Throws for a reader's HDF5 call that failed at `where`, consuming HDF5's error stack: if
// HDF5 recorded an environment errno, EnvironmentError "<where>: <action>: <strerror(errno)>
// (HDF5: <reason>)" (e.g. "cannot open the segment: Permission denied"); otherwise the file's
// content is the likely cause: InputError "<where>: <corrupt> (HDF5: <reason>)".
[[noreturn]] void throw_hdf5_read_failure(const std::string& where, const std::string& action,
                                          const std::string& corrupt);

// Scalar attributes on an object (a file's root group: pass the file id). Writers return
// false on an HDF5 error; readers return nullopt if the attribute is missing or not of the
// expected class (string / integer).
bool write_string_attribute(hid_t object, const char* name, const std::string& value);
bool write_int_attribute(hid_t object, const char* name, long long value);
std::optional<std::string> read_string_attribute(hid_t object, const char* name);
std::optional<long long> read_int_attribute(hid_t object, const char* name);

}  // namespace hapstate::blobs_detail
