#!/usr/bin/env bash
# The test suite: installs what is missing, builds stvd (Release) with its
# tests and runs them with CTest.
#
# STVD_BUILD_DIR overrides the build directory (default: build).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${STVD_BUILD_DIR:-build}

bash scripts/setup.sh
# MRtrix3 for the walk-through test of docs/mrtrix.md (about 20 MB to
# download); without it, that one test is skipped.
bash scripts/setup.sh mrtrix3 ||
  echo "test.sh: mrtrix3 is not installed; the MRtrix walk-through test will be skipped"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSTVD_BUILD_TESTS=ON
cmake --build "$build_dir" -j"$(nproc)"
# Every test takes seconds; 300 s means one has hung. Tests may set a
# TIMEOUT property of their own.
ctest --test-dir "$build_dir" --output-on-failure -j2 --timeout 300
