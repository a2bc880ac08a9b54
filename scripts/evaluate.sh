#!/usr/bin/env bash
# The evaluation: installs what is missing (gnuplot included), builds stvd
# (Release) with its benchmarks, runs every experiment of docs/benchmarks.md
# and rewrites that document and its plots (docs/benchmarks/*.png) from the
# figures of this run. Takes about 45 minutes on two cores.
#
# STVD_BUILD_DIR overrides the build directory (default: build).
# STVD_EVALUATION_QUICK=1 runs small sizes only (a few minutes; for checking
# the script, not for the document). STVD_EVALUATION_ACCURACY_TABLE=1 adds
# the 128^3 accuracy tables of stvd_accuracy_table (about 50 minutes more).
# The comparison with Hamiltonian Fast Marching is not run here (HFM is not
# a dependency): scripts/hfm_comparison.py writes
# docs/benchmarks/hfm_comparison.tsv, which the document includes.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${STVD_BUILD_DIR:-build}
run_dir=out/evaluation
quick=${STVD_EVALUATION_QUICK:-0}

bash scripts/setup.sh gnuplot-nox
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DSTVD_BUILD_BENCHMARKS=ON
cmake --build "$build_dir" -j"$(nproc)" \
  --target stvd_evaluation stvd_accuracy_table stvd_propagation_speed stvd_path_tracing \
  stvd_surface_speed stvd_surface_steiner_table stvd_brain_comparison stvd_tool
# The tetrahedral-mesh benchmark exists only when the optional TetGen module
# is built (STVD_WITH_TETGEN); build it when it is there.
# (grep reads all of the list: with -q it would stop early, make would die of
# SIGPIPE, and under pipefail the test would fail even with the target there.)
if cmake --build "$build_dir" --target help | grep stvd_tet_mesh_speed >/dev/null; then
  cmake --build "$build_dir" -j"$(nproc)" --target stvd_tet_mesh_speed
fi

rm -rf "$run_dir"
mkdir -p "$run_dir"
bench="$build_dir/bench"

{
  echo "date=$(date -u '+%Y-%m-%d %H:%M UTC')"
  # docs/ is left out of the comparison: it is what this script writes, and
  # documents edited while a run goes on do not change what it measures.
  echo "commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD -- . ':(exclude)docs' 2>/dev/null || echo ' (with local changes)')"
  echo "cpu=$(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)"
  echo "cores=$(nproc)"
  echo "memory=$(free -g | awk '/^Mem:/ {print $2 " GiB"}')"
  echo "compiler=$(c++ --version | head -1)"
  echo "load_start=$(cut -d' ' -f1-3 /proc/loadavg)"
} >"$run_dir/machine.txt"

if [[ $quick == 1 ]]; then
  sweep_size=24 accuracy_size=32 speed_size=64 scale_sizes="32 48 64" repeats=1
  steiner_size=12 steiner_max=4 parallel_size=32 surface_size=32 surface_steiner_max=4
  convergence_size=64 plane_size=40 bend_size=32
else
  sweep_size=64 accuracy_size=128 speed_size=128 scale_sizes="64 96 128 192 256" repeats=3
  steiner_size=32 steiner_max=8 parallel_size=96 surface_size=96 surface_steiner_max=16
  convergence_size=128 plane_size=100 bend_size=64
fi

echo "evaluate.sh: error versus time (${sweep_size}^3)"
"$bench/stvd_evaluation" sweep --size "$sweep_size" --repeats "$repeats" >"$run_dir/sweep.tsv"
echo "evaluate.sh: Lanthier's Steiner points next to Dijkstra and STVD (${steiner_size}^3)"
"$bench/stvd_evaluation" sweep --size "$steiner_size" --repeats "$repeats" --steiner-max "$steiner_max" \
  >"$run_dir/steiner_sweep.tsv"
echo "evaluate.sh: refinement"
"$bench/stvd_evaluation" refinement --repeats "$repeats" >"$run_dir/refinement.tsv"
echo "evaluate.sh: convergence under refinement at the defaults (32^3 to ${convergence_size}^3)"
"$bench/stvd_evaluation" convergence --size "$convergence_size" --repeats "$repeats" >"$run_dir/convergence.tsv"
echo "evaluate.sh: the curved scene over the anisotropy and the shear slope (${bend_size}^3)"
"$bench/stvd_evaluation" bend --size "$bend_size" --gammas 2,5,10,20 --repeats 1 >"$run_dir/bend.tsv"
echo "evaluate.sh: a flat plane under a constant anisotropic metric (${plane_size}^2 cells)"
"$bench/stvd_evaluation" plane --size "$plane_size" --repeats "$repeats" >"$run_dir/plane.tsv"
echo "evaluate.sh: scale ($scale_sizes)"
first=1
for n in $scale_sizes; do
  # One process per size, so that each peak memory is that size's own.
  if ((first)); then header=(); first=0; else header=(--no-header); fi
  "$bench/stvd_evaluation" scale --size "$n" "${header[@]}" >>"$run_dir/scale.tsv"
done
echo "evaluate.sh: masked volumes"
"$bench/stvd_evaluation" mask --size "$accuracy_size" --repeats "$repeats" >"$run_dir/mask.tsv"
echo "evaluate.sh: many source sets on 1 and 2 threads (${parallel_size}^3)"
"$bench/stvd_evaluation" parallel --size "$parallel_size" --repeats "$repeats" >"$run_dir/parallel.tsv"
echo "evaluate.sh: time per relaxed edge"
# Repetitions interleaved, so that each ratio to Dijkstra compares runs made
# under the same load.
"$bench/stvd_propagation_speed" --benchmark_filter="n:$speed_size/k:(0|4|6|8)/" --benchmark_enable_random_interleaving=true \
  --benchmark_repetitions="$((repeats + 2))" --benchmark_report_aggregates_only=true \
  --benchmark_format=json >"$run_dir/propagation_speed.json"
# The 128^3 accuracy tables (every k, three shear slopes, other stencils,
# each method alternating with Dijkstra) add about 50 minutes; the sweep
# above covers error versus k at 64^3. STVD_EVALUATION_ACCURACY_TABLE=1
# runs them too.
if [[ ${STVD_EVALUATION_ACCURACY_TABLE:-0} == 1 ]]; then
  echo "evaluate.sh: accuracy versus k (${accuracy_size}^3)"
  "$bench/stvd_accuracy_table" --size "$accuracy_size" --repeats "$repeats" >"$run_dir/accuracy_table.md"
fi
gbench_options=(--benchmark_repetitions="$((repeats + 2))" --benchmark_report_aggregates_only=true
  --benchmark_format=json)
if [[ $quick == 1 ]]; then gbench_options=(--benchmark_format=json --benchmark_min_time=0.01); fi
echo "evaluate.sh: path tracing"
"$bench/stvd_path_tracing" "${gbench_options[@]}" >"$run_dir/path_tracing.json"
echo "evaluate.sh: surfaces"
"$bench/stvd_surface_speed" "${gbench_options[@]}" >"$run_dir/surface_speed.json"
echo "evaluate.sh: Lanthier on surfaces (${surface_size}^2)"
"$bench/stvd_surface_steiner_table" --size "$surface_size" --max-steiner "$surface_steiner_max" \
  >"$run_dir/section_surface_steiner.md"
# Surfaces against exact polyhedral geodesics (CGAL's data meshes and the
# test oracle, built when CGAL is found) and, under the curvature metric,
# against Lanthier M = 16: the tables of docs/surfaces.md.
oracle="$build_dir/tests/surface/stvd_exact_geodesic_oracle"
if cmake --build "$build_dir" --target help | grep stvd_exact_geodesic_oracle >/dev/null; then
  cmake --build "$build_dir" -j"$(nproc)" --target stvd_exact_geodesic_oracle stvd_surface_exact_table
  surface_meshes="armadillo elephant cheese fandisk turbine blade" surface_repeats=5
  if [[ $quick == 1 ]]; then surface_meshes="elephant" surface_repeats=1; fi
  mesh_dir="$run_dir/meshes"
  mkdir -p "$mesh_dir"
  header=()
  for mesh in $surface_meshes; do
    echo "evaluate.sh: surface $mesh against exact geodesics"
    (cd "$mesh_dir" && cmake -E tar xzf /usr/share/doc/libcgal-dev/data.tar.gz "data/meshes/$mesh.off")
    for source in 0 2000; do
      "$oracle" "$mesh_dir/data/meshes/$mesh.off" "$source" "$mesh_dir/$mesh.$source.txt"
      "$bench/stvd_surface_exact_table" "$mesh_dir/data/meshes/$mesh.off" --source "$source" \
        --exact "$mesh_dir/$mesh.$source.txt" --repeats "$surface_repeats" "${header[@]}" >>"$run_dir/surface_exact.tsv"
      header=(--no-header)
    done
  done
  header=()
  for gamma in 10 20; do
    for mesh in $surface_meshes; do
      echo "evaluate.sh: surface $mesh, curvature metric $gamma, against Lanthier M = 16"
      "$bench/stvd_surface_exact_table" "$mesh_dir/data/meshes/$mesh.off" --source 0 --curvature "$gamma" \
        --repeats "$surface_repeats" "${header[@]}" >>"$run_dir/surface_curvature.tsv"
      header=(--no-header)
    done
  done
fi
if [[ -x $bench/stvd_tet_mesh_speed ]]; then
  echo "evaluate.sh: tetrahedral meshes"
  tet_filter=.
  # Quick mode: the small box mesh only (TetGen takes a while for the large
  # one); the error table and the L-shaped prism are small.
  if [[ $quick == 1 ]]; then tet_filter='grid|vol_milli:200/|tetMeshRule|tetMeshNotch'; fi
  # The repetitions of all the benchmarks alternate, so that the ratios to
  # Dijkstra compare runs made under the same load.
  "$bench/stvd_tet_mesh_speed" "${gbench_options[@]}" --benchmark_enable_random_interleaving=true \
    --benchmark_filter="$tet_filter" >"$run_dir/tet_mesh_speed.json"
fi
echo "evaluate.sh: the shipped brain against Lanthier's Steiner points"
brain_steiner=8
if [[ $quick == 1 ]]; then brain_steiner=2; fi
"$bench/stvd_brain_comparison" sample_data/dti_philips_biobank/dti_tensor_dipy5d.nii.gz \
  --seed-voxel 55,54,15 --steiner "$brain_steiner" >"$run_dir/brain_comparison.tsv"
echo "evaluate.sh: real brain"
"$build_dir/tools/stvd" distance sample_data/dti_philips_biobank/dti_tensor_dipy5d.nii.gz \
  --seed-voxel 55,54,15 -o "$run_dir/cc_body_distance.nii.gz" --stats "$run_dir/brain_stats.json"

echo "load_end=$(cut -d' ' -f1-3 /proc/loadavg)" >>"$run_dir/machine.txt"
python3 scripts/evaluation_report.py "$run_dir" docs
echo "evaluate.sh: wrote docs/benchmarks.md and docs/benchmarks/*.png from $run_dir"
