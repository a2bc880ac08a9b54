#!/usr/bin/env bash
# The test suite: installs what is missing, builds stvd (Release) with its
# tests and runs them with CTest, then the sanitizer and fuzz smoke pass.
#
# STVD_BUILD_DIR overrides the build directory (default: build);
# STVD_SANITIZE=0 skips the sanitizer pass.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${STVD_BUILD_DIR:-build}

bash scripts/setup.sh
# MRtrix3 for the walk-through test of docs/mrtrix.md and the FOD fits by
# dwi2fod (docs/fod.md, "Validation"; about 20 MB to download); without it,
# those tests are skipped.
bash scripts/setup.sh mrtrix3 ||
  echo "test.sh: mrtrix3 is not installed; the tests that run MRtrix will be skipped"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSTVD_BUILD_TESTS=ON
cmake --build "$build_dir" -j"$(nproc)"
# Every test takes seconds; 300 s means one has hung. Tests may set a
# TIMEOUT property of their own.
ctest --test-dir "$build_dir" --output-on-failure -j2 --timeout 300
# The suites of everything that reads or writes files again under
# AddressSanitizer and UndefinedBehaviorSanitizer, after a few seconds of
# each fuzz target (scripts/sanitize.sh; docs/reliability.md, "Sanitizers",
# gives what runs and its time on CI's 2 cores). STVD_SANITIZE=0 leaves
# this pass out.
if [[ ${STVD_SANITIZE:-1} != 0 ]]; then
  bash scripts/sanitize.sh
fi
