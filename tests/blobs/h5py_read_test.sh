#!/usr/bin/env bash
# Precomputes the beam scene, then reads its blobs with Debian's h5py through our HDF5 filter
# plugin (build/plugins) and checks them against the catalogue (h5py_read_test.py).
set -euo pipefail
build=$1
source=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$build/tools/hapstate" run "$source/pipelines/beam/scene.toml" --state "$dir/state" -q --no-compact >/dev/null
# Debian's python (with python3-h5py), not another python3 that may come first in PATH; only our
# plugin directory, so no other HDF5 plugin is loaded.
HDF5_PLUGIN_PATH="$build/plugins" /usr/bin/python3 "$source/tests/blobs/h5py_read_test.py" "$dir/state"
