#!/usr/bin/env bash
# The MRtrix walk-through of docs/mrtrix.md, run as a test: MRtrix's
# dwi2tensor fits the shipped diffusion data, stvd computes a distance map
# and geodesic paths from the .mif it wrote, and MRtrix's own tools check
# the results: mrinfo reads stvd's .mif output on the tensors' grid, and
# tckmap's track density is non-zero at the seed and at every target and
# zero outside the brain mask.
#
# Usage: scripts/mrtrix_walkthrough.sh [STVD]   (default: build/tools/stvd)
# Needs Debian's mrtrix3 (scripts/setup.sh mrtrix3); without it the script
# says so and exits 77, which CTest reports as skipped.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
stvd=$(realpath "${1:-build/tools/stvd}")

for tool in dwi2tensor mrconvert mrinfo tckmap mrstats mrcalc; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "mrtrix_walkthrough.sh: MRtrix3's $tool is not installed (Debian: apt-get install mrtrix3); skipped"
    exit 77
  fi
done

D=$PWD/sample_data/dti_philips_biobank
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cd "$out"
export MRTRIX_QUIET=1
start=$SECONDS

# 1. MRtrix fits the tensors. The mask is converted first: MRtrix stores
#    images in its own axis order (here the first axis reversed), and stvd
#    wants the mask on the tensors' grid as stored.
mrconvert "$D/dti_mask.nii.gz" mask.mif
dwi2tensor -fslgrad "$D/dwi.bvec" "$D/dwi.bval" -mask mask.mif "$D/dwi.nii.gz" dt.mif

# 2. stvd reads dt.mif as it is (order mrtrix, scanner frame) and writes
#    .mif. Seed and targets are the RAS millimetres of seeds.tsv: the same
#    points in every tool, whatever each numbers its voxels.
seed=6.39,11.57,76.31                                 # CC_body, voxel 55,54,15 in seeds.tsv
targets=(-7.57,11.22,82.39 18.38,12.43,78.22          # CC_body_L_lateral 62,54,18, CC_body_R_lateral 49,54,16
         -19.11,1.44,69.15 34.68,6.76,70.61)          # CST_L 68,50,11, CST_R 41,51,12
voxels=(55,54,15 62,54,18 49,54,16 68,50,11 41,51,12)  # the same points as seeds.tsv's voxels (NIfTI order)
"$stvd" distance dt.mif --mask mask.mif --seed-point "$seed" --unreachable-value nan -o cc_body.mif
target_options=()
for t in "${targets[@]}"; do target_options+=(--target-point "$t"); done
"$stvd" path dt.mif --mask mask.mif --seed-point "$seed" "${target_options[@]}" -o paths.tck

fail() { echo "mrtrix_walkthrough.sh: FAILED: $*" >&2; exit 1; }
stat() { mrstats "$@" | tr -d ' '; }  # one number, without mrstats' padding

# 3. MRtrix reads the distance map on the tensors' grid.
[[ $(mrinfo cc_body.mif -size) == "112 112 32" ]] || fail "mrinfo: size $(mrinfo cc_body.mif -size)"
[[ $(mrinfo cc_body.mif -transform) == "$(mrinfo dt.mif -transform)" ]] || fail "mrinfo: another transform than dt.mif"
echo "distance map: $(stat cc_body.mif -mask mask.mif -output count -ignorezero) voxels of the mask reached (besides the seed)"

# 4. tckmap: the track density of the paths, at the seed and every target
#    (seeds.tsv's NIfTI voxels, which stvd info translates into MRtrix's
#    numbering) and outside the mask.
tckmap paths.tck -template mask.mif density.mif
for voxel in "${voxels[@]}"; do
  shown=$("$stvd" info "$D/dti_tensor_dipy5d.nii.gz" --voxel "$voxel" |
          sed -n 's/.* in stvd = (\([0-9]*\), \([0-9]*\), \([0-9]*\)) in MRtrix.*/\1 \2 \3/p')
  read -r i j k <<<"$shown"
  density=$(mrconvert density.mif -coord 0 "$i" -coord 1 "$j" -coord 2 "$k" - | stat - -output max)
  echo "track density at voxel $voxel (MRtrix $i,$j,$k): $density"
  [[ $density != 0 ]] || fail "no track passes voxel $voxel (MRtrix $i,$j,$k)"
done
outside=$(mrcalc density.mif mask.mif 0 -eq -mult - | stat - -output max)
echo "largest track density outside the mask: $outside"
[[ $outside == 0 ]] || fail "tracks outside the mask (density $outside)"
echo "mrtrix_walkthrough.sh: passed in $((SECONDS - start)) s"
