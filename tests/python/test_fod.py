"""FOD images (docs/fod.md) read and evaluated by stvd, held to DIPY and
MRtrix3 themselves: spherical-harmonic coefficients written with NumPy and
NiBabel in each of DIPY's bases, legacy and not, evaluated by stvd along
directions of its physical frame (LPS) and by DIPY along the same
directions in DIPY's frame (the voxel axes); MRtrix images in MRtrix3's
basis and scanner frame; crossings simulated and fitted by DIPY's CSD whose
amplitude maxima, found through stvd's reader and evaluation, lie on the
true fibres also when the image has a rotated and flipped affine; and
hostile files refused in one line. stvd's evaluation is reached through the
test helper stvd_fod_probe (tests/itk/fod_probe.cpp)."""

import os
import pathlib
import shutil
import subprocess
import warnings

import nibabel as nib
import numpy as np
import pytest

from dipy.core.gradients import gradient_table
from dipy.core.sphere import Sphere
from dipy.data import get_sphere
from dipy.direction import peak_directions
from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel
from dipy.reconst.shm import real_sh_tournier, sh_to_sf
from dipy.sims.voxel import multi_tensor
from fod_phantoms import crossing_fit, write_mif

BUILD = pathlib.Path(os.environ.get("STVD_BUILD_DIR", pathlib.Path(__file__).resolve().parents[2] / "build"))
PROBE = pathlib.Path(os.environ.get("STVD_FOD_PROBE", BUILD / "tests" / "itk" / "stvd_fod_probe"))
RAS_TO_LPS = np.diag([-1.0, -1.0, 1.0])

# DIPY's (basis_type, legacy) and stvd's name for the same functions.
DIPY_BASES = [
    ("tournier07", False, "tournier07"),
    ("tournier07", True, "tournier07_legacy"),
    ("descoteaux07", False, "descoteaux07"),
    ("descoteaux07", True, "descoteaux07_legacy"),
]


def probe(path, basis, frame, voxels, directions_lps):
    """stvd's amplitudes at (voxel, LPS direction) pairs."""
    queries = pathlib.Path(str(path) + ".queries")
    np.savetxt(queries, np.c_[np.asarray(voxels, float), directions_lps], fmt="%.17g")
    run = subprocess.run([str(PROBE), str(path), basis, frame, str(queries)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return np.loadtxt(run.stdout.splitlines()[1:], ndmin=1)


def refused(path, basis="-", frame="-"):
    """The one-line message with which stvd refuses a file."""
    queries = pathlib.Path(str(path) + ".queries")
    queries.write_text("")
    run = subprocess.run([str(PROBE), str(path), basis, frame, str(queries)], capture_output=True, text=True)
    assert run.returncode == 3, (run.returncode, run.stdout, run.stderr)
    line = run.stderr.strip()
    assert "\n" not in line and str(path) in line, line
    return line


def rotated_flipped_affine():
    """A NIfTI affine (RAS) with an oblique rotation, a flipped axis and
    anisotropic voxels."""
    angle = np.radians(35.0)
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    affine = np.eye(4)
    affine[:3, :3] = rotation @ np.diag([-1.0, 1.0, 1.0]) @ np.diag([2.0, 2.5, 3.0])
    affine[:3, 3] = [12.0, -30.0, 4.0]
    return affine


def voxel_to_lps(affine):
    """The matrix taking a direction along the voxel axes (DIPY's frame) to LPS."""
    axes = affine[:3, :3] / np.linalg.norm(affine[:3, :3], axis=0)
    return RAS_TO_LPS @ axes


def unit_directions(rng, count):
    d = rng.normal(size=(count, 3))
    return d / np.linalg.norm(d, axis=1)[:, None]


def dipy_amplitudes(coefficients, directions, basis_type, legacy):
    """DIPY's sh_to_sf of each row of coefficients at its own direction."""
    lmax = int(round((np.sqrt(8 * coefficients.shape[-1] + 1) - 3) / 2))
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for c, d in zip(coefficients, directions):
            sphere = Sphere(xyz=d[None, :])
            out.append(sh_to_sf(c, sphere, sh_order=lmax, basis_type=basis_type, legacy=legacy)[0])
    return np.array(out)


@pytest.mark.parametrize("basis_type,legacy,name", DIPY_BASES)
@pytest.mark.parametrize("lmax", [2, 8, 12])
def test_dipy_bases_evaluate_as_dipy_does_along_the_voxel_axes(tmp_path, basis_type, legacy, name, lmax):
    rng = np.random.default_rng(lmax * 10 + len(name))
    count = (lmax + 1) * (lmax + 2) // 2
    coefficients = rng.normal(size=(3, 2, 2, count)).astype(np.float32)
    affine = rotated_flipped_affine()
    path = tmp_path / "fod.nii.gz"
    nib.save(nib.Nifti1Image(coefficients, affine), path)

    voxels = np.c_[rng.integers(0, 3, 50), rng.integers(0, 2, 50), rng.integers(0, 2, 50)]
    directions_voxel = unit_directions(rng, 50)
    reference = dipy_amplitudes(coefficients[voxels[:, 0], voxels[:, 1], voxels[:, 2]].astype(np.float64),
                                directions_voxel, basis_type, legacy)
    ours = probe(path, name, "-", voxels, directions_voxel @ voxel_to_lps(affine).T)
    assert np.max(np.abs(ours - reference)) <= 1e-5 * np.max(np.abs(reference))
    # The same along the antipodes: an FOD has even degrees only.
    ours = probe(path, name, "-", voxels, -directions_voxel @ voxel_to_lps(affine).T)
    assert np.max(np.abs(ours - reference)) <= 1e-5 * np.max(np.abs(reference))




def test_mrtrix_images_are_mrtrix3s_basis_in_the_scanner_frame(tmp_path):
    rng = np.random.default_rng(7)
    coefficients = rng.normal(size=(2, 3, 2, 45)).astype(np.float32)
    affine = rotated_flipped_affine()
    path = tmp_path / "fod.mif"
    write_mif(path, coefficients, affine)
    voxels = np.c_[rng.integers(0, 2, 50), rng.integers(0, 3, 50), rng.integers(0, 2, 50)]
    directions_ras = unit_directions(rng, 50)
    reference = dipy_amplitudes(coefficients[voxels[:, 0], voxels[:, 1], voxels[:, 2]].astype(np.float64),
                                directions_ras, "tournier07", False)
    ours = probe(path, "-", "-", voxels, directions_ras @ RAS_TO_LPS.T)
    assert np.max(np.abs(ours - reference)) <= 1e-5 * np.max(np.abs(reference))

    # MRtrix3's own sh2amp agrees: its basis is DIPY's tournier07 without
    # legacy, taken along the scanner axes whatever the image's transform.
    if shutil.which("sh2amp") is None:
        pytest.skip("MRtrix3 is not installed")
    one = coefficients[1, 2, 1]
    write_mif(tmp_path / "one.mif", one.reshape(1, 1, 1, 45), affine)
    np.savetxt(tmp_path / "dirs.txt", directions_ras)
    subprocess.run(["sh2amp", "-quiet", "one.mif", "dirs.txt", "amp.nii"], cwd=tmp_path, check=True)
    mrtrix = np.asanyarray(nib.load(tmp_path / "amp.nii").dataobj).ravel()
    ours = probe(tmp_path / "one.mif", "-", "-", np.zeros((50, 3)), directions_ras @ RAS_TO_LPS.T)
    assert np.max(np.abs(ours - mrtrix)) <= 1e-5 * np.max(np.abs(mrtrix))


@pytest.mark.skipif(shutil.which("amp2sh") is None, reason="MRtrix3 is not installed")
def test_mrtrix_fits_spherical_harmonics_along_the_scanner_axes(tmp_path):
    # A signal that is (g . u)^2 for a direction u of the scanner, given with
    # gradient directions in the scanner frame (MRtrix's dw_scheme) in an
    # image with a rotated, flipped transform: amp2sh's coefficients peak
    # along u in the scanner frame, not along the voxel axes.
    rng = np.random.default_rng(11)
    affine = rotated_flipped_affine()
    gradients = unit_directions(rng, 90)
    u = np.array([1.0, 0.3, 0.2]) / np.linalg.norm([1.0, 0.3, 0.2])
    signal = (gradients @ u) ** 2
    nib.save(nib.Nifti1Image(signal.reshape(1, 1, 1, -1).astype(np.float32), affine), tmp_path / "dwi.nii")
    np.savetxt(tmp_path / "grad.b", np.c_[gradients, np.full(90, 1000.0)])
    subprocess.run(["mrconvert", "-quiet", "dwi.nii", "-grad", "grad.b", "dwi.mif"], cwd=tmp_path, check=True)
    subprocess.run(["amp2sh", "-quiet", "-lmax", "4", "dwi.mif", "sh.mif"], cwd=tmp_path, check=True)
    across = np.cross(u, [0.0, 0.0, 1.0])
    across /= np.linalg.norm(across)
    ours = probe(tmp_path / "sh.mif", "-", "-", np.zeros((2, 3)), np.array([u, across]) @ RAS_TO_LPS.T)
    assert ours == pytest.approx([1.0, 0.0], abs=1e-4)


def csd_crossing(angle_degrees):
    """One voxel of two equal fibres crossing at the angle (DIPY's
    multi_tensor, b = 3000 along 100 directions, no noise), fitted with
    DIPY's CSD at lmax 8 (coefficients in descoteaux07_legacy, DIPY 1.6's
    basis for CSD), and the true fibre directions along the voxel axes."""
    sphere = get_sphere("repulsion100")
    gtab = gradient_table(np.r_[0.0, np.full(100, 3000.0)], np.r_[np.zeros((1, 3)), sphere.vertices])
    evals = np.array([0.0017, 0.0002, 0.0002])
    signal, sticks = multi_tensor(gtab, np.array([evals, evals]), S0=100,
                                  angles=[(90, 20), (90, 20 + angle_degrees)], fractions=[50, 50], snr=None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = ConstrainedSphericalDeconvModel(gtab, (evals, 100.0), sh_order=8).fit(signal)
    return fit, np.asarray(sticks)


def angle_degrees(a, b):
    return np.degrees(np.arccos(min(1.0, abs(float(np.dot(a, b))))))


@pytest.mark.parametrize("crossing", [90, 45])
@pytest.mark.parametrize("oriented", ["identity", "rotated_flipped"])
def test_csd_maxima_through_stvd_lie_on_the_true_fibres(tmp_path, crossing, oriented):
    fit, sticks = csd_crossing(crossing)
    affine = np.eye(4) if oriented == "identity" else rotated_flipped_affine()
    path = tmp_path / "csd.nii.gz"
    nib.save(nib.Nifti1Image(fit.shm_coeff.reshape(1, 1, 1, -1).astype(np.float32), affine), path)

    # A dense sphere along the voxel axes, carried into LPS; stvd evaluates
    # along the LPS directions, and its maxima are compared in LPS.
    dense = get_sphere("repulsion724").subdivide(2)
    to_lps = voxel_to_lps(affine)
    sphere_lps = Sphere(xyz=dense.vertices @ to_lps.T, faces=dense.faces)
    ours = probe(path, "descoteaux07_legacy", "-", np.zeros((len(dense.vertices), 3)), sphere_lps.vertices)
    peaks, _, _ = peak_directions(ours, sphere_lps, relative_peak_threshold=0.3, min_separation_angle=15)
    assert len(peaks) == 2
    truth = sticks @ to_lps.T
    for fibre in truth:
        assert min(angle_degrees(p, fibre) for p in peaks) < 3.0
    # And they are DIPY's own maxima of its own evaluation, carried into LPS.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dipy_odf = fit.odf(dense)
    dipy_peaks, _, _ = peak_directions(dipy_odf, dense, relative_peak_threshold=0.3, min_separation_angle=15)
    for p in dipy_peaks @ to_lps.T:
        assert min(angle_degrees(p, q) for q in peaks) < 1e-3
    assert np.max(np.abs(ours - dipy_odf)) <= 1e-5 * np.max(np.abs(dipy_odf))


def test_hostile_files_are_refused_in_one_line(tmp_path):
    affine = rotated_flipped_affine()
    wrong = tmp_path / "seven.nii.gz"
    nib.save(nib.Nifti1Image(np.zeros((2, 2, 2, 7), np.float32), affine), wrong)
    assert "7 volumes is no spherical-harmonic count" in refused(wrong, "descoteaux07")

    values = np.ones((2, 2, 2, 15), np.float32)
    values[1, 0, 1, 4] = np.nan
    nan = tmp_path / "nan.nii.gz"
    nib.save(nib.Nifti1Image(values, affine), nan)
    assert "coefficient 4 of voxel (1, 0, 1) is NaN" in refused(nan, "descoteaux07")
    values[1, 0, 1, 4] = np.inf
    nib.save(nib.Nifti1Image(values, affine), nan)
    assert "coefficient 4 of voxel (1, 0, 1) is infinite" in refused(nan, "descoteaux07")

    whole = tmp_path / "whole.nii"
    nib.save(nib.Nifti1Image(np.ones((4, 4, 4, 45), np.float32), affine), whole)
    truncated = tmp_path / "truncated.nii"
    truncated.write_bytes(whole.read_bytes()[:-100])
    refused(truncated, "tournier07")

    assert "does not say its spherical-harmonic basis" in refused(whole)
    assert "unknown spherical-harmonic basis" in refused(whole, "dipy")
    scalar = tmp_path / "scalar.nii.gz"
    nib.save(nib.Nifti1Image(np.ones((4, 4, 4), np.float32), affine), scalar)
    assert "fourth axis" in refused(scalar, "tournier07")


def crossing_phantom(angle):
    """The crossing phantom's CSD coefficients (zero outside the bundles,
    as a fit's mask leaves them), its axes and in_bundle (fod_phantoms.py)."""
    fit, axes, in_bundle = crossing_fit(angle)
    return fit.shm_coeff.astype(np.float32), axes, in_bundle


def fod_path(path, seed, target):
    """stvd's Dijkstra under the convexified FOD norm: the target's distance
    and the voxels of its path."""
    run = subprocess.run([str(PROBE), str(path), "descoteaux07_legacy", "-", "--path", *map(str, seed), *map(str, target)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.strip().split("\n")[1:]
    return float(lines[0]), np.loadtxt(lines[1:], ndmin=2).astype(int)


@pytest.mark.parametrize("crossing", [90, 45])
@pytest.mark.parametrize("oriented", ["identity", "rotated_flipped"])
def test_dijkstra_on_a_csd_crossing_follows_the_seeds_own_bundle(tmp_path, crossing, oriented):
    # Voxels of 2 mm, the grid rotated and flipped or not: the bundles'
    # physical lengths follow from the affine, the lobes from DIPY's voxel
    # frame carried into LPS by stvd.
    coefficients, axes, in_bundle = crossing_phantom(crossing)
    affine = np.diag([2.0, 2.0, 2.0, 1.0])
    if oriented == "rotated_flipped":
        affine[:3, :3] = voxel_to_lps(rotated_flipped_affine()) @ np.diag([2.0, 2.0, 2.0])
        affine[:3, 3] = [5.0, -7.0, 3.0]
    path = tmp_path / "crossing.nii.gz"
    nib.save(nib.Nifti1Image(coefficients, affine), path)

    # The far end of the seed's bundle: reached straight along it, through
    # the crossing, at its length (20 voxels of 2 mm).
    distance, voxels = fod_path(path, (0, 10, 1), (20, 10, 1))
    assert distance == pytest.approx(40.0, rel=0.005)
    assert all(j == 10 and k == 1 for _, j, k in voxels), voxels

    # The far end of the other bundle: along the seed's bundle to the
    # crossing, then along the other; no voxel outside both, the length
    # that of the two legs.
    target = (int(round(10 + 10 * axes[1][0])), int(round(10 + 10 * axes[1][1])), 1)
    distance, voxels = fod_path(path, (0, 10, 1), target)
    legs = 2.0 * (10 + np.hypot(target[0] - 10, target[1] - 10))
    assert distance == pytest.approx(legs, rel=0.02)
    assert all(in_bundle(0, i, j) or in_bundle(1, i, j) for i, j, _ in voxels), voxels
