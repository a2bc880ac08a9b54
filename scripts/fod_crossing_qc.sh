#!/usr/bin/env bash
# Tensor against FOD paths through the centrum semiovale crossings of the
# shipped brain (docs/fod.md, "Paths through the crossing"), as QC pages:
# `stvd path --report` under the tensors (sample_data/dti_philips_biobank,
# the tool's default method) and under the FOD slab
# (sample_data/fod_philips_biobank, --fod-basis mrtrix3), for the two
# corticospinal paths (one run: a seed below each crossing, a target above)
# and the callosal path (left to right through both crossings), and the
# index of the four pages: OUTDIR/index.html. scripts/demo.sh runs it;
# tests/python/test_fod_sample_paths.py runs it and measures its paths.
#
# Usage: scripts/fod_crossing_qc.sh [OUTDIR]   (default: out/fod_crossing of the working folder)
# STVD_EXECUTABLE names the tool (default: ${STVD_BUILD_DIR:-build}/tools/stvd);
# STVD_PYTHON the interpreter with NiBabel that writes the box mask
# (default: /usr/bin/python3).
set -euo pipefail
# OUTDIR and a relative STVD_EXECUTABLE are the caller's; the default tool
# and the sample data are the repository's.
out=$(realpath -m -- "${1:-out/fod_crossing}")
tool=${STVD_EXECUTABLE:+$(realpath -m -- "$STVD_EXECUTABLE")}
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tool=${tool:-${STVD_BUILD_DIR:-build}/tools/stvd}
python=${STVD_PYTHON:-/usr/bin/python3}
dti=sample_data/dti_philips_biobank
fod=sample_data/fod_philips_biobank
mkdir -p "$out"

# Both metrics run in the same box around the crossings (the slab's mask in
# slab voxels i 30..81, j 44..61, all 12 slices; the same voxels on the
# tensors' grid, whose slice k is the slab's k + 10), so that the FOD's
# table of F* is small (11,232 voxels).
# Isolated (-I): no module of the working folder or of PYTHONPATH runs. The
# masks are written to a fresh name in the output folder and renamed over
# their own, so that a link or FIFO planted under that name is replaced,
# never written through.
"$python" -I - "$fod/fod_mask_slab.nii.gz" "$dti/dti_mask.nii.gz" "$out" <<'EOF'
import os
import sys
import tempfile
import nibabel as nib
import numpy as np
slab_path, dti_path, out = sys.argv[1:]


umask = os.umask(0)
os.umask(umask)


def save(image, name):
    handle, staged = tempfile.mkstemp(dir=out, prefix=".stvd-", suffix=".nii.gz")
    os.fchmod(handle, 0o666 & ~umask)  # as a file the user's umask makes, not mkstemp's 0600
    os.close(handle)
    try:
        image.to_filename(staged)
        os.replace(staged, os.path.join(out, name))
    except BaseException:
        os.unlink(staged)
        raise


slab = nib.load(slab_path)
box = np.zeros(slab.shape, bool)
box[30:82, 44:62, :] = True
box &= np.asanyarray(slab.dataobj) > 0
save(nib.Nifti1Image(box.astype(np.uint8), slab.affine), "box_mask_slab.nii.gz")
dti = nib.load(dti_path)
on_dti = np.zeros(dti.shape, np.uint8)
on_dti[:, :, 10:10 + box.shape[2]] = box
save(nib.Nifti1Image(on_dti, dti.affine), "box_mask_dti.nii.gz")
EOF

# The points (docs/fod.md): CST from slab slice 1 below each crossing to
# slice 10 above it, CC from beyond the left crossing to beyond the right one.
fod_run=("$fod/fod_csd_lmax4_slab.nii.gz" --fod-basis mrtrix3 --mask "$out/box_mask_slab.nii.gz" --threads 2)
tensor_run=("$dti/dti_tensor_dipy5d.nii.gz" --mask "$out/box_mask_dti.nii.gz")
"$tool" path "${fod_run[@]}" --seed-voxel 67,54,1 --seed-voxel 41,54,1 \
  --target-voxel 68,53,10 --target-voxel 42,52,10 -o "$out/cst_fod.tck" --report "$out/cst_fod.html" --subject cst_fod -q
"$tool" path "${tensor_run[@]}" --seed-voxel 67,54,11 --seed-voxel 41,54,11 \
  --target-voxel 68,53,20 --target-voxel 42,52,20 -o "$out/cst_tensor.tck" --report "$out/cst_tensor.html" --subject cst_tensor -q
"$tool" path "${fod_run[@]}" --seed-voxel 78,54,6 --target-voxel 32,54,6 \
  -o "$out/cc_fod.tck" --report "$out/cc_fod.html" --subject cc_fod -q
"$tool" path "${tensor_run[@]}" --seed-voxel 78,54,16 --target-voxel 32,54,16 \
  -o "$out/cc_tensor.tck" --report "$out/cc_tensor.html" --subject cc_tensor -q
"$tool" report --index "$out" -o "$out/index.html" -q
