#!/usr/bin/env bash
# Installs the Debian (bookworm) packages bcassim builds and runs with, when missing.
# Idempotent: does nothing when every package is already installed.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  libeigen3-dev libsuitesparse-dev libopenblas0-pthread libtbb-dev
  libvtk9-dev libcgal-dev libyaml-cpp-dev libcli11-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev libopenmpi-dev
  python3 python3-dev python3-matplotlib python3-numpy python3-scipy python3-pytest pybind11-dev  # the Python module (import bcassim) and its pytest suites
  openmpi-bin  # mpirun: the MPI executor (assimilate --mpi) and its 3-rank test
  libscalapack-openmpi-dev  # the full-state UKF's Cholesky factor shared by the MPI ranks
  zlib1g-dev liblz4-dev liblzma-dev  # the compressors of VTK XML files, read by io/VtkXmlReader
  clang-format clang-tidy  # make lint: the formatting and the bug-finding checks CI runs
  clang-14 libclang-rt-14-dev  # make fuzz: libFuzzer, AddressSanitizer and UBSan runtimes
  libopenigtlink-dev openigtlink-examples  # bcassim serve/replay; the examples are a third-party client for the end-to-end test
  xvfb xauth  # a virtual X display: VTK 9.1 on Debian renders the demo picture through X
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "bcassim: installing missing Debian packages: ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
    SUDO=sudo
  else
    echo "bcassim: not root; run: sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
else
  SUDO=
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
