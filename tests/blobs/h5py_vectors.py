"""Reading one vector of a blob segment with Debian's h5py, through the segment's index
(docs/storage.md, "Layout (format 2)"); shared by tests/blobs/h5py_read_test.py and the Python
package's tests (tests/python). Needs our zstd filter plugin on HDF5_PLUGIN_PATH."""
import numpy as np


def vector(f, group, leaf):
    """The vector group/leaf of an open segment, through its index."""
    groups = bytes(f["hapstate_index/groups"][()]).decode().split("\n")[:-1]
    for table in f["hapstate_index"]:
        if table == "groups":
            continue
        name = f[table].attrs.get("hapstate_leaf", table)
        if (name.decode() if isinstance(name, bytes) else name) != leaf:
            continue
        assert f[table].ndim == 2 and "32015" in f[table]._filters, f[table]._filters  # zstd, by the plugin
        for row, (g, length) in enumerate(f["hapstate_index/" + table][()]):
            if groups[g] == group:
                return np.asarray(f[table][row, :length])
    raise KeyError(group + "/" + leaf)
