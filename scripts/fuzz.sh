#!/usr/bin/env bash
# Runs every libFuzzer target in fuzz/ for a given time, one after the other,
# at the lowest CPU priority. Usage:
#
#   bash scripts/fuzz.sh SECONDS [TARGET...]
#
# Builds the targets with clang (Debian's clang-14) into build-fuzz/ (or
# STVD_FUZZ_BUILD_DIR), then for each target: replays its regression inputs
# (fuzz/regressions/TARGET/), and fuzzes from its seed corpus
# (fuzz/corpus/TARGET/) plus what earlier runs found (kept in the build
# folder, never written back into fuzz/). Each run is limited to 2 GB of
# memory and 10 s per input; a crash, a leak, an escaping exception, a hang
# or an allocation beyond the limit stops that target and leaves the input
# in BUILD/fuzz-findings/TARGET/. STVD_FUZZ_JOBS=N runs N targets at once.
# The last lines give executions, coverage (libFuzzer's cov and ft) and
# findings per target.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

seconds=${1:?usage: scripts/fuzz.sh SECONDS [TARGET...]}
shift
build_dir=${STVD_FUZZ_BUILD_DIR:-build-fuzz}
jobs=${STVD_FUZZ_JOBS:-1}

all_targets=$(sed -n 's/^stvd_add_fuzz_target(\([a-z_0-9]*\).*/\1/p' fuzz/CMakeLists.txt)
targets=${*:-$all_targets}

bash scripts/setup.sh
CC=clang-14 CXX=clang++-14 cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSTVD_BUILD_FUZZERS=ON -DSTVD_BUILD_TESTS=OFF -DSTVD_BUILD_BENCHMARKS=OFF \
  -DSTVD_WITH_OPENVDB=OFF -DSTVD_WITH_TETGEN=OFF >/dev/null
# shellcheck disable=SC2086
nice -n 19 cmake --build "$build_dir" -j"$(nproc)" --target $(printf 'fuzz_%s ' $targets)

export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/fuzz/itk_leaks.supp:print_suppressions=0}

run_target() {
  local target=$1 binary="$build_dir/fuzz/fuzz_$1"
  local work="$build_dir/fuzz-work/$target" findings="$build_dir/fuzz-findings/$target"
  mkdir -p "$work" "$findings"
  local log="$build_dir/fuzz-work/$target.log"
  local regressions=()
  if [[ -d fuzz/regressions/$target ]] && compgen -G "fuzz/regressions/$target/*" >/dev/null; then
    regressions=("fuzz/regressions/$target")
  fi
  local status=0
  # Sanitizer reports go to files beside the findings: the readers divert
  # standard error while a library runs (library_messages.hpp).
  ASAN_OPTIONS=detect_leaks=1:log_path=$PWD/$findings/report \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1:log_path=$PWD/$findings/report \
  nice -n 19 "$binary" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/" \
    "$work" "fuzz/corpus/$target" "${regressions[@]}" >"$log" 2>&1 || status=$?
  local runs cov ft
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  # Crashes, leaks, timeouts and out-of-memory inputs are findings; a slow
  # unit (one input over 10 s of wall time, which a busy machine alone can
  # cause) is counted apart, to be replayed and timed by hand.
  local found slow
  found=$(find "$findings" -type f -name '[a-z]*-*' ! -name 'report*' ! -name 'slow-unit-*' | wc -l)
  slow=$(find "$findings" -type f -name 'slow-unit-*' | wc -l)
  printf 'fuzz: %-16s %5ss  %10s executions  cov %5s  ft %6s  findings %s%s%s\n' "$target" "$seconds" \
    "${runs:-?}" "${cov:-?}" "${ft:-?}" "$found" "$( ((slow > 0)) && echo "  slow units $slow")" \
    "$([[ $status -ne 0 ]] && echo "  (stopped, see $log)")"
  return "$status"
}

failed=0
if ((jobs > 1)); then
  pids=()
  for t in $targets; do
    run_target "$t" & pids+=($!)
    while (($(jobs -rp | wc -l) >= jobs)); do wait -n || failed=1; done
  done
  wait "${pids[@]}" 2>/dev/null || failed=1
else
  for t in $targets; do run_target "$t" || failed=1; done
fi
exit "$failed"
