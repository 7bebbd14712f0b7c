#!/usr/bin/env bash
# Installs the Debian packages hapstate needs to build, test and run (see docs/dependencies.md).
# Idempotent: does nothing when every package is already installed. Needs root (or sudo).
# Arguments: extra packages a script needs besides these (scripts/fuzz.sh: clang's).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev              # dense/sparse linear algebra, fixed-size element kernels
  libsuitesparse-dev         # CHOLMOD sparse Cholesky (UMFPACK present as well)
  libopenblas0-pthread       # optimised BLAS for CHOLMOD's supernodal factorisation (10x over reference BLAS)
  libhdf5-dev                # configuration vectors (blobs)
  libsqlite3-dev             # state catalogue
  libzstd-dev                # compression of stored vectors (HDF5 filter 32015)
  zlib1g-dev                 # zlib-compressed VTK XML (.vtu) meshes
  libtomlplusplus-dev        # scene files
  libcli11-dev               # command-line parsing
  nlohmann-json3-dev         # JSON output of hapstate-inspect
  libgmsh-dev                # tetrahedralising closed STL/OBJ surfaces
  libopenmpi-dev openmpi-bin # hapstate-expand across MPI ranks and hosts (mpirun)
  libgtest-dev libbenchmark-dev
  libnanoflann-dev           # only bench/contact_bench's k-d tree comparison (optional there)
  calculix-ccx               # the independent reference solver used by the tests
  python3 python3-matplotlib # plots and comparison scripts
  python3-h5py               # the test that a foreign HDF5 reader decodes our blobs
  pybind11-dev python3-pybind11 python3-numpy python3-pytest  # the Python package and its tests
  libjs-three                # three.js for hapstate-view's page, served locally
  chromium                   # the viewer's test in a real (headless) browser
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
