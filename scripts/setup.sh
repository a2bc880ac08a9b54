#!/usr/bin/env bash
# Installs the Debian 12 packages that stvd needs to build, test and run its
# demo. Does nothing (and needs no root) when they are all installed already.
set -euo pipefail

# Compiler and build tools; GoogleTest and Google Benchmark; the libraries of
# the adapters (ITK, Eigen, TetGen, OpenVDB; Debian's FindOpenVDB.cmake also
# wants Boost.Iostreams; zlib for .mif.gz and the checks of gzip streams);
# Python with NiBabel and NumPy for the tests that check written NIfTI files
# independently of ITK; for the Python package stvd, its headers and
# pybind11, and what its tests and example use (DIPY, pytest, tqdm,
# matplotlib, which also draws the QC reports that the tests open in
# headless Chromium; pip and venv for the tests of `pip install .`, whose
# build backend needs nothing else); clang with its sanitizer and libFuzzer runtimes
# for the sanitizer and fuzzing builds (scripts/sanitize.sh,
# scripts/fuzz.sh); CGAL (header-only, GPL) for the exact-geodesic oracle of
# the surface tests only, and CGAL's data archive (libcgal-demo), whose
# meshes those tests read; Dask's distributed scheduler and Nipype for
# cohort runs (stvd cohort, stvd.interfaces), and cryptography, with which
# the embedded Dask cluster of a cohort run makes the TLS keys that keep
# other users of the machine out of it; pandas for the package's
# connectivity tables (Connectivity.to_dataframe) and their test; doxygen
# for the API reference generated from the headers (docs/library.md) and
# its test.
packages=(
  g++ cmake make libgtest-dev libbenchmark-dev clang-14 libclang-rt-14-dev
  libinsighttoolkit5-dev libeigen3-dev libtet1.5-dev libopenvdb-dev libboost-iostreams-dev zlib1g-dev
  python3-nibabel python3-numpy
  python3-dev pybind11-dev python3-pybind11 python3-dipy python3-pytest python3-tqdm python3-matplotlib
  python3-pip python3-setuptools python3-wheel python3-venv
  libcgal-dev libcgal-demo
  python3-distributed python3-nipype python3-cryptography python3-pandas
  chromium
  doxygen
)
# Scripts with needs of their own name extra packages as arguments
# (scripts/evaluate.sh: gnuplot for its plots).
packages+=("$@")

if ! command -v dpkg-query >/dev/null 2>&1; then
  echo "setup.sh: dpkg-query not found; this script installs Debian 12 packages:" >&2
  echo "  ${packages[*]}" >&2
  exit 1
fi

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$package" 2>/dev/null || true)
  [[ $status == "install ok installed" ]] || missing+=("$package")
done

if ((${#missing[@]} == 0)); then
  echo "setup.sh: all ${#packages[@]} required Debian packages are installed"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  echo "setup.sh: missing Debian packages: ${missing[*]}" >&2
  echo "setup.sh: run this script as root, or install them with" >&2
  echo "  sudo apt-get install -y --no-install-recommends ${missing[*]}" >&2
  exit 1
fi

echo "setup.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${packages[@]}" </dev/null
