"""A crossing of two fibre bundles made by DIPY: the FOD tests' phantom
(test_fod.py through stvd's reader, test_fod_distance.py through the
package, test_fod_crossings.py fitted by DIPY and by MRtrix3), and the
MRtrix image writer those tests share."""

import pathlib
import subprocess
import warnings

import nibabel as nib
import numpy as np

from dipy.core.gradients import gradient_table
from dipy.data import get_sphere
from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel
from dipy.sims.voxel import multi_tensor


def crossing_signal(angle):
    """A 21 x 21 x 3 phantom of 2 mm voxels: bundle 0 along the voxel axis i
    through j = 10, bundle 1 at `angle` to it in the i-j plane through the
    centre, each 5 voxels wide, DIPY's multi_tensor signal (b = 3000, 100
    directions, no noise; two equal fibres in the crossing, 50 % each).
    Returns the gradient table, the fibres' eigenvalues, the signal, the
    mask of the bundles, the mask of their single-fibre voxels, the bundles'
    axes (voxel frame) and in_bundle(b, i, j), whether voxel (i, j, .) lies
    in bundle b."""
    sphere = get_sphere("repulsion100")
    gtab = gradient_table(np.r_[0.0, np.full(100, 3000.0)], np.r_[np.zeros((1, 3)), sphere.vertices])
    evals = np.array([0.0017, 0.0002, 0.0002])
    axes = [np.array([1.0, 0.0, 0.0]), np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle)), 0.0])]

    def in_bundle(b, i, j):
        x = np.array([i - 10.0, j - 10.0, 0.0])
        return np.linalg.norm(x - (x @ axes[b]) * axes[b]) <= 2 + 1e-9

    signals = {}
    for key, angles in (((0,), [(90, 0), (90, 0)]), ((1,), [(90, angle), (90, angle)]),
                        ((0, 1), [(90, 0), (90, angle)])):
        signals[key], _ = multi_tensor(gtab, np.array([evals, evals]), S0=100, angles=angles, fractions=[50, 50],
                                       snr=None)
    data = np.zeros((21, 21, 3, 101))
    mask = np.zeros((21, 21, 3), bool)
    single = np.zeros((21, 21, 3), bool)
    for i in range(21):
        for j in range(21):
            key = tuple(b for b in (0, 1) if in_bundle(b, i, j))
            if key:
                data[i, j, :] = signals[key]
                mask[i, j, :] = True
                single[i, j, :] = len(key) == 1
    return gtab, evals, data, mask, single, axes, in_bundle


def crossing_fit(angle):
    """The phantom of crossing_signal fitted by DIPY's CSD (lmax 8, the
    true fibre's response) inside the bundles. Returns the fit, the
    bundles' axes (voxel frame) and in_bundle(b, i, j)."""
    gtab, evals, data, mask, _, axes, in_bundle = crossing_signal(angle)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ConstrainedSphericalDeconvModel(gtab, (evals, 100.0), sh_order=8).fit(data, mask=mask)
    return fit, axes, in_bundle


# What MRtrix3's commands get to run before a test gives up on them (they
# take about 3 s on a quiet machine, and a loaded one is far slower).
MRTRIX_TIMEOUT = 600


def mrtrix_crossing_fod(angle, directory):
    """The phantom of crossing_signal fitted by MRtrix3 (`dwi2response
    manual` from the single-fibre voxels, `dwi2fod csd` at lmax 8 inside
    the bundles), each command a child process with a timeout. The DWI is
    written with the affine diag(2, 2, 2): its scanner axes are the voxel
    axes, so MRtrix's gradient table (scanner frame) is DIPY's. Returns the
    path of the FOD image (.mif: MRtrix3's basis, scanner frame), its
    coefficients (read from its NIfTI copy), the axes and in_bundle."""
    gtab, _, data, mask, single, axes, in_bundle = crossing_signal(angle)
    directory = pathlib.Path(directory)
    affine = np.diag([2.0, 2.0, 2.0, 1.0])
    nib.save(nib.Nifti1Image(data.astype(np.float32), affine), directory / "dwi.nii")
    nib.save(nib.Nifti1Image(mask.astype(np.uint8), affine), directory / "mask.nii")
    nib.save(nib.Nifti1Image(single.astype(np.uint8), affine), directory / "single_fibre.nii")
    np.savetxt(directory / "gradients.b", np.c_[gtab.bvecs, gtab.bvals])
    for command in (["mrconvert", "dwi.nii", "-grad", "gradients.b", "dwi.mif"],
                    ["dwi2response", "manual", "dwi.mif", "single_fibre.nii", "response.txt", "-shells", "0,3000",
                     "-scratch", str(directory)],
                    ["dwi2fod", "csd", "dwi.mif", "response_b3000.txt", "fod.mif", "-mask", "mask.nii", "-lmax", "8"],
                    ["mrconvert", "fod.mif", "fod.nii"]):
        if command[0] == "dwi2fod":
            # CSD deconvolves the b = 3000 shell: the response's last row.
            rows = [r for r in (directory / "response.txt").read_text().splitlines() if not r.startswith("#")]
            (directory / "response_b3000.txt").write_text(rows[-1] + "\n")
        run = subprocess.run([*command, "-quiet", "-nthreads", "1"], cwd=directory, capture_output=True, text=True,
                             timeout=MRTRIX_TIMEOUT)
        assert run.returncode == 0, (command, run.stderr)
    coefficients = np.asanyarray(nib.load(directory / "fod.nii").dataobj)
    return directory / "fod.mif", coefficients, axes, in_bundle


def write_mif(path, data, affine):
    """An MRtrix image written byte by byte: float32, axes stored in order,
    the transform of a NIfTI-style affine (RAS), as MRtrix's format says."""
    spacing = np.linalg.norm(affine[:3, :3], axis=0)
    rotation = affine[:3, :3] / spacing
    lines = ["mrtrix image", "dim: " + ",".join(map(str, data.shape)),
             "vox: " + ",".join(f"{s:.17g}" for s in spacing) + ",1",
             "layout: +0,+1,+2,+3", "datatype: Float32LE"]
    for r in range(3):
        lines.append("transform: " + ",".join(f"{v:.17g}" for v in [*rotation[r], affine[r, 3]]))
    head = "\n".join(lines) + "\n"
    offset = (len(head) + 32 + 3) // 4 * 4
    header = (head + f"file: . {offset}\nEND\n").ljust(offset)
    path.write_bytes(header.encode() + np.asarray(data, "<f4").tobytes(order="F"))
