#!/usr/bin/env bash
# The demo: installs what is missing, builds stvd (Release): the tool and the
# Python package, and computes the anisotropic geodesic distance from a seed
# voxel in the body of the corpus callosum over the shipped DTI sample,
# written to out/cc_body_distance.nii.gz, with its QC report
# out/cc_body_report.html (docs/report.md); then the distance from the same
# voxel under the metric of the shipped FOD slab (MRtrix3's CSD of the same
# DWI; docs/fod.md, "Real data"), out/cc_body_fod_distance.nii.gz on the
# slab's grid (slices 10 to 21 of the tensors'); and the QC pages of tensor
# against FOD paths through the centrum semiovale crossings
# (scripts/fod_crossing_qc.sh): out/fod_crossing/index.html.
#
# STVD_BUILD_DIR overrides the build directory (default: build).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${STVD_BUILD_DIR:-build}

bash scripts/setup.sh
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
# Only the command-line tool (stvd_tool is the target of <build>/tools/stvd),
# the Python package (stvd_python: <build>/python/stvd) and what they link;
# scripts/test.sh builds the rest.
cmake --build "$build_dir" -j"$(nproc)" --target stvd_tool stvd_python

mkdir -p out
"$build_dir/tools/stvd" distance sample_data/dti_philips_biobank/dti_tensor_dipy5d.nii.gz \
  --seed-voxel 55,54,15 -o out/cc_body_distance.nii.gz --report out/cc_body_report.html
# The FOD slab's seed is the same voxel: slice 15 of the DWI is the slab's 5.
"$build_dir/tools/stvd" distance sample_data/fod_philips_biobank/fod_csd_lmax4_slab.nii.gz --fod-basis mrtrix3 \
  --mask sample_data/fod_philips_biobank/fod_mask_slab.nii.gz --seed-voxel 55,54,5 -o out/cc_body_fod_distance.nii.gz
# Corticospinal and callosal paths through the crossings, tensor against FOD
# (docs/fod.md, "Paths through the crossing"): four pages and their index.
STVD_EXECUTABLE="$build_dir/tools/stvd" bash scripts/fod_crossing_qc.sh out/fod_crossing
echo "The QC report of this run: $(pwd)/out/cc_body_report.html (open it in a browser; docs/report.md)"
echo "Tensor against FOD paths through the crossings: $(pwd)/out/fod_crossing/index.html (docs/fod.md)"
echo "The Python package is in $build_dir/python: PYTHONPATH=$build_dir/python python3 -c \"import stvd\" (docs/python.md)"
