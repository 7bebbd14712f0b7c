// Our zstd filter (id 32015) as an HDF5 dynamically loaded filter plugin, so that any HDF5
// program -- h5dump, h5py, ParaView -- reads state-directory segments with
// HDF5_PLUGIN_PATH=<build>/plugins (docs/storage.md). Built as build/plugins/libhapstate_h5zstd.so.
#include "blobs/zstd_filter.h"

#include <H5PLextern.h>

extern "C" {

H5PL_type_t H5PLget_plugin_type(void) { return H5PL_TYPE_FILTER; }

const void* H5PLget_plugin_info(void) { return hapstate::zstd_filter_class(); }

}  // extern "C"
