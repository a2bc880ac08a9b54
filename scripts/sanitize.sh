#!/usr/bin/env bash
# The sanitizer pass of the test command: builds stvd, its tests and the
# fuzz targets with clang, AddressSanitizer and UndefinedBehaviorSanitizer
# into build-sanitize/ (or STVD_SANITIZE_BUILD_DIR), then
#   1. replays every regression input of fuzz/regressions/ and fuzzes each
#      target for a few seconds (STVD_FUZZ_SMOKE_SECONDS, default 3);
#   2. runs the suites of everything that reads or writes files: CTest
#      labels itk, outputs, surface, tetmesh and tetgen (the imaging adapter,
#      the tool, its outputs, surfaces, tetrahedral meshes), and the core's
#      suites of file identity, output transactions and input validation.
#      Left out, and why (docs/reliability.md, "Sanitizers"): the core's
#      propagation suites (they read no files, and take most of the pass's
#      time under the sanitizers), the exact surface references (a CGAL
#      oracle, most of a minute per mesh under AddressSanitizer, and the
#      accuracy tests that need it), and the tool's memory check
#      (ToolMemoryCheck: it measures the memory of the uninstrumented tool,
#      and AddressSanitizer needs terabytes of address space, which its
#      `ulimit -v` can never give).
# Any sanitizer report fails the pass; reports are written to
# BUILD/sanitizer-reports/ (the readers divert standard error while a
# library runs) and printed at the end.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${STVD_SANITIZE_BUILD_DIR:-build-sanitize}
smoke_seconds=${STVD_FUZZ_SMOKE_SECONDS:-3}

bash scripts/setup.sh
CC=clang-14 CXX=clang++-14 cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=None \
  -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" -DCMAKE_C_FLAGS="-O1 -gline-tables-only" \
  -DSTVD_BUILD_FUZZERS=ON -DSTVD_BUILD_TESTS=ON -DSTVD_BUILD_BENCHMARKS=OFF \
  -DSTVD_WITH_OPENVDB=OFF -DSTVD_WITH_TETGEN=OFF >/dev/null
cmake --build "$build_dir" -j"$(nproc)"

reports="$PWD/$build_dir/sanitizer-reports"
rm -rf "$reports"
mkdir -p "$reports"
export ASAN_OPTIONS="detect_leaks=1:log_path=$reports/report"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$reports/report"
# Suppressed leaks are not reported, and their summary is not printed
# either: any file in the reports folder is a finding.
export LSAN_OPTIONS="suppressions=$PWD/fuzz/itk_leaks.supp:print_suppressions=0"
# The instrumented tool runs 3 to 5 times slower than the Release one: the
# tests give each of its runs 30 minutes instead of 10 (test_support.cpp).
export STVD_TEST_TOOL_TIMEOUT=${STVD_TEST_TOOL_TIMEOUT:-1800}

status=0
for target in $(sed -n 's/^stvd_add_fuzz_target(\([a-z_0-9]*\).*/\1/p' fuzz/CMakeLists.txt); do
  scratch="$build_dir/fuzz-smoke/$target"
  rm -rf "$scratch"
  mkdir -p "$scratch"
  inputs=("fuzz/corpus/$target")
  [[ -d fuzz/regressions/$target ]] && inputs+=("fuzz/regressions/$target")
  if "$build_dir/fuzz/fuzz_$target" -max_total_time="$smoke_seconds" -timeout=10 -rss_limit_mb=2048 \
       -malloc_limit_mb=2048 -artifact_prefix="$scratch/" "$scratch" "${inputs[@]}" >"$scratch.log" 2>&1; then
    echo "sanitize: fuzz smoke $target: $(sed -n 's/.*Done \([0-9]*\) runs.*/\1/p' "$scratch.log") runs, no finding"
  else
    echo "sanitize: fuzz smoke $target FAILED (see $scratch.log and $reports)"
    status=1
  fi
done

ctest --test-dir "$build_dir" -L 'itk|outputs|surface|tetmesh|tetgen' \
  -E '^ToolMemoryCheck\.|^surface_exact_reference_|RealMesh|^NonManifoldAgainstExactGeodesics\.' \
  --output-on-failure -j2 --timeout 1200 || status=1
ctest --test-dir "$build_dir" -L core -R '^(FileIdentity|OutputTransactionTest|PropagationInputs|MetricFieldInputs|CellMeshInputs)\.' \
  --output-on-failure -j2 --timeout 1200 || status=1
if compgen -G "$reports/report*" >/dev/null; then
  echo "sanitize: sanitizer reports:"
  cat "$reports"/report*
  status=1
fi
exit "$status"
