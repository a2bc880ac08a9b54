#!/usr/bin/env bash
# Builds stvd the way a program that only links it would (-DSTVD_LIBRARY_ONLY=ON,
# shared, without ITK), installs it into a scratch prefix and checks it:
# versioned SONAME, no stvd::detail symbol exported (nm -D), every library
# resolving against the others, LICENSE and a working `pkg-config --cflags
# --libs stvd` (tests/packaging/library_only_build.cmake). Prints the CPU time
# the build took. A few CPU-minutes, so not part of the test suite.
#   scripts/check_library_build.sh [SCRATCH_DIR]   (default: build-library-check)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
work=${1:-build-library-check}
mkdir -p "$work"
work=$(cd "$work" && pwd)
start=$(date +%s)
cmake -DSOURCE_DIR="$PWD" -DWORK_DIR="$work" -DCXX_COMPILER="$(command -v c++)" \
      -DGENERATOR="Unix Makefiles" -P tests/packaging/library_only_build.cmake
# The CPU time of the finished children (fields cutime and cstime of /proc/self/stat).
ticks=$(getconf CLK_TCK)
read -r child_user child_system < <(awk '{print $16, $17}' /proc/$$/stat)
echo "check_library_build: $(( $(date +%s) - start )) s wall, $(( (child_user + child_system) / ticks )) CPU-seconds"
