// The HDF5 zstd filter: HDF5 registered filter id 32015, the id and chunk format of the
// standard HDF5 zstd plugin (HDF5Plugin-Zstandard, hdf5plugin's Zstd, the HDF Group's
// hdf5_plugins). Each filtered chunk is one complete zstd frame with the content size in its
// header; cd_values[0] holds the compression level. So files we write are read by h5py with
// hdf5plugin (or HDF5_PLUGIN_PATH pointing at any of those plugins), and we read theirs.
#pragma once

namespace hapstate {

// Registered HDF5 filter id of zstd (https://portal.hdfgroup.org/.../registered-filter-plugins).
inline constexpr int kZstdFilterId = 32015;

// zstd level used when a writer does not ask for another (1 = fastest .. 22 = smallest).
inline constexpr int kDefaultZstdLevel = 3;

// Registers the filter with the HDF5 library of this process. Idempotent and thread-safe:
// the first call registers, later calls return at once. Throws InputError if HDF5 refuses
// the registration (the next call retries). Every blob reader and writer calls it; call it
// yourself only when you use the HDF5 C API directly on our files.
void register_zstd_filter();

// The filter's H5Z_class2_t (as const void*, so hdf5.h stays out of this header): what the
// dynamically loadable plugin (blobs/h5z_zstd_plugin.cc, build/plugins/) hands to HDF5.
const void* zstd_filter_class();

}  // namespace hapstate
