#include "blobs/zstd_filter.h"

#include "util/error.h"

#include <hdf5.h>
#include <zstd.h>

#include <algorithm>
#include <mutex>

namespace hapstate {
namespace {

// Decompresses a frame whose header does not carry the content size (frames written by a
// streaming compressor): grow the output until the frame is consumed. Returns 0 on error.
size_t decompress_unknown_size(const void* in, size_t in_bytes, void** out_buf, size_t* out_size) {
  ZSTD_DStream* stream = ZSTD_createDStream();
  if (stream == nullptr) return 0;
  size_t capacity = std::max<size_t>(in_bytes * 4, ZSTD_DStreamOutSize());
  void* out = H5allocate_memory(capacity, false);
  ZSTD_inBuffer input{in, in_bytes, 0};
  ZSTD_outBuffer output{out, capacity, 0};
  size_t result = 0;
  bool ok = out != nullptr;
  while (ok) {
    result = ZSTD_decompressStream(stream, &output, &input);
    if (ZSTD_isError(result)) {
      ok = false;
      break;
    }
    if (result == 0) break;  // frame complete
    if (input.pos == input.size && output.pos < output.size) {
      ok = false;
      break;
    }  // truncated
    if (output.pos == output.size) {
      capacity *= 2;
      void* bigger = H5resize_memory(out, capacity);
      if (bigger == nullptr) {
        ok = false;
        break;
      }
      out = bigger;
      output.dst = out;
      output.size = capacity;
    }
  }
  ZSTD_freeDStream(stream);
  if (!ok) {
    if (out != nullptr) H5free_memory(out);
    return 0;
  }
  *out_buf = out;
  *out_size = capacity;
  return output.pos;
}

// The H5Z_func_t callback. On failure it returns 0 and leaves *buf untouched (HDF5's rule).
size_t zstd_filter(unsigned int flags, size_t cd_nelmts, const unsigned int cd_values[],
                   size_t nbytes, size_t* buf_size, void** buf) {
  if ((flags & H5Z_FLAG_REVERSE) != 0) {
    const unsigned long long content = ZSTD_getFrameContentSize(*buf, nbytes);
    if (content == ZSTD_CONTENTSIZE_ERROR) return 0;
    void* out = nullptr;
    size_t out_size = 0;
    size_t produced = 0;
    if (content == ZSTD_CONTENTSIZE_UNKNOWN) {
      produced = decompress_unknown_size(*buf, nbytes, &out, &out_size);
      if (produced == 0) return 0;
    } else {
      out_size = static_cast<size_t>(content);
      out = H5allocate_memory(std::max<size_t>(out_size, 1), false);
      if (out == nullptr) return 0;
      produced = ZSTD_decompress(out, out_size, *buf, nbytes);
      if (ZSTD_isError(produced) || produced != out_size) {
        H5free_memory(out);
        return 0;
      }
    }
    H5free_memory(*buf);
    *buf = out;
    *buf_size = out_size;
    return produced;
  }
  int level = cd_nelmts > 0 ? static_cast<int>(cd_values[0]) : kDefaultZstdLevel;
  level = std::clamp(level, 1, ZSTD_maxCLevel());
  const size_t bound = ZSTD_compressBound(nbytes);
  void* out = H5allocate_memory(bound, false);
  if (out == nullptr) return 0;
  const size_t written = ZSTD_compress(out, bound, *buf, nbytes, level);
  if (ZSTD_isError(written)) {
    H5free_memory(out);
    return 0;
  }
  H5free_memory(*buf);
  *buf = out;
  *buf_size = bound;
  return written;
}

const H5Z_class2_t kZstdClass = {
    H5Z_CLASS_T_VERS,
    static_cast<H5Z_filter_t>(kZstdFilterId),
    1,  // encoder present
    1,  // decoder present
    "Zstandard compression: http://www.zstd.net",
    nullptr,  // can_apply: any type, any chunk
    nullptr,  // set_local: cd_values are set by the writer
    zstd_filter,
};

}  // namespace

const void* zstd_filter_class() { return &kZstdClass; }

void register_zstd_filter() {
  static std::once_flag once;
  std::call_once(once, [] {
    // No library shutdown at exit (before HDF5 initialises; a no-op if something else used
    // HDF5 first). A segment whose write failed (a full disk) cannot be closed: HDF5 1.10
    // keeps it open, and its shutdown at exit then retries the failing flush and prints
    // "HDF5: infinite loop closing library" after our message. Nothing needs that shutdown:
    // a writer that was not closed is deleted anyway (SegmentWriter), readers only read.
    H5dont_atexit();
    if (H5Zregister(&kZstdClass) < 0) {
      throw InputError("HDF5: cannot register the zstd filter (id 32015) with the HDF5 library");
    }
  });
}

}  // namespace hapstate
