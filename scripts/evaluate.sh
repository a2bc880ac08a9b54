#!/usr/bin/env bash
# The evaluation: installs what is missing (gnuplot included), builds stvd
# (Release) with its benchmarks, runs every experiment of docs/benchmarks.md
# and rewrites that document and its plots (docs/benchmarks/*.png) from the
# figures of this run. Takes about half an hour on two cores.
#
# STVD_BUILD_DIR overrides the build directory (default: build).
# STVD_EVALUATION_QUICK=1 runs small sizes only (a few minutes; for checking
# the script, not for the document).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${STVD_BUILD_DIR:-build}
run_dir=out/evaluation
quick=${STVD_EVALUATION_QUICK:-0}

bash scripts/setup.sh gnuplot-nox
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSTVD_BUILD_BENCHMARKS=ON
cmake --build "$build_dir" -j"$(nproc)" \
  --target stvd_evaluation stvd_accuracy_table stvd_propagation_speed stvd_tool

rm -rf "$run_dir"
mkdir -p "$run_dir"
bench="$build_dir/bench"

{
  echo "date=$(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD 2>/dev/null || echo ' (with local changes)')"
  echo "cpu=$(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)"
  echo "cores=$(nproc)"
  echo "memory=$(free -g | awk '/^Mem:/ {print $2 " GiB"}')"
  echo "compiler=$(c++ --version | head -1)"
} >"$run_dir/machine.txt"

if [[ $quick == 1 ]]; then
  sweep_size=24 accuracy_size=32 speed_size=64 scale_sizes="32 48 64" repeats=1
else
  sweep_size=64 accuracy_size=128 speed_size=128 scale_sizes="64 96 128 192 256" repeats=3
fi

echo "evaluate.sh: error versus time (${sweep_size}^3)"
"$bench/stvd_evaluation" sweep --size "$sweep_size" --repeats "$repeats" >"$run_dir/sweep.tsv"
echo "evaluate.sh: refinement"
"$bench/stvd_evaluation" refinement --repeats "$repeats" >"$run_dir/refinement.tsv"
echo "evaluate.sh: scale ($scale_sizes)"
first=1
for n in $scale_sizes; do
  # One process per size, so that each peak memory is that size's own.
  if ((first)); then header=(); first=0; else header=(--no-header); fi
  "$bench/stvd_evaluation" scale --size "$n" "${header[@]}" >>"$run_dir/scale.tsv"
done
echo "evaluate.sh: masked volumes"
"$bench/stvd_evaluation" mask --size "$accuracy_size" --repeats "$repeats" >"$run_dir/mask.tsv"
echo "evaluate.sh: time per relaxed edge"
"$bench/stvd_propagation_speed" --benchmark_filter="n:$speed_size/k:(0|5|8)/" \
  --benchmark_repetitions="$((repeats + 2))" --benchmark_report_aggregates_only=true \
  --benchmark_format=json >"$run_dir/propagation_speed.json"
echo "evaluate.sh: accuracy versus k (${accuracy_size}^3)"
"$bench/stvd_accuracy_table" --size "$accuracy_size" --repeats "$repeats" >"$run_dir/accuracy_table.md"
echo "evaluate.sh: real brain"
"$build_dir/tools/stvd" distance sample_data/dti_philips_biobank/dti_tensor_dipy5d.nii.gz \
  --seed-voxel 55,54,15 -o "$run_dir/cc_body_distance.nii.gz" --stats "$run_dir/brain_stats.json"

python3 scripts/evaluation_report.py "$run_dir" docs
echo "evaluate.sh: wrote docs/benchmarks.md and docs/benchmarks/*.png from $run_dir"
