"""Real data, small: DIPY's small_64D (a 10 x 10 x 10 crop of a human brain
scan, 2 mm voxels, 64 directions at b ~ 1000 and one b = 0; it ships with
Debian's python3-dipy, BSD-3; docs/fod.md, "Real data"), fitted by DIPY's
CSD and by MRtrix3's `dwi2fod csd`, through stvd.fod_distance and the tool.
What real data lets one check without ground truth: the package's map is
the tool's byte for byte, finite everywhere in the volume (the whole crop
is brain), never below the straight-line distance |x - s| (F* >= |v|: no
direction costs less than 1 per mm), and the map's cheapest step from a
seed follows the FOD's largest peak there; the two fitters' peaks agree in
physical space (the frames of the b-vectors, the fits and stvd's reader
agree)."""

import pathlib
import shutil
import subprocess
import warnings

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import TOOL

dipy_data = pytest.importorskip("dipy.data")
from dipy.core.gradients import gradient_table  # noqa: E402
from dipy.data import get_sphere  # noqa: E402
from dipy.direction import peak_directions  # noqa: E402
from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel, auto_response_ssst  # noqa: E402
from dipy.reconst.shm import sh_to_sf  # noqa: E402

MRTRIX_TIMEOUT = 600
RAS_TO_LPS = np.diag([-1.0, -1.0, 1.0])


@pytest.fixture(scope="module")
def small_64d(tmp_path_factory):
    """The DWI (NIfTI path, data, affine), its b-values and b-vectors with
    row 0 (NaN in the file) zeroed, written as FSL files."""
    try:
        names = dipy_data.get_fnames("small_64D")
    except Exception as error:  # DIPY without its bundled files
        pytest.skip(f"DIPY's small_64D is not installed: {error}")
    dwi, bval, bvec = map(pathlib.Path, names)
    bvecs = np.loadtxt(bvec)
    assert np.isnan(bvecs[0]).all() and not np.isnan(bvecs[1:]).any()  # the file's known flaw
    bvecs[0] = 0.0
    directory = tmp_path_factory.mktemp("small_64d")
    np.savetxt(directory / "bvecs", bvecs.T, fmt="%.10f")
    image = nib.load(dwi)
    return {"dwi": dwi, "bval": bval, "bvecs_file": directory / "bvecs", "bvals": np.loadtxt(bval),
            "bvecs": bvecs, "data": np.asanyarray(image.dataobj).astype(float), "affine": image.affine,
            "directory": directory}


@pytest.fixture(scope="module")
def dipy_fit(small_64d):
    gtab = gradient_table(small_64d["bvals"], small_64d["bvecs"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        response, _ = auto_response_ssst(gtab, small_64d["data"], roi_radii=10, fa_thr=0.7)
        return ConstrainedSphericalDeconvModel(gtab, response, sh_order=8).fit(small_64d["data"])


@pytest.fixture(scope="module")
def mrtrix_fod(small_64d):
    """MRtrix3's fit: `dwi2response tournier -number 50` (its default of 300
    single-fibre voxels is more than 10^3 voxels hold), `dwi2fod csd` (lmax
    8), both with the zeroed b-vectors as FSL's; child processes with a
    timeout. Returns the .mif path and its coefficients as NIfTI."""
    missing = [c for c in ("dwi2response", "dwi2fod", "mrconvert") if shutil.which(c) is None]
    if missing:
        pytest.skip(f"MRtrix3 is not installed ({', '.join(missing)} not found)")
    d = small_64d["directory"]
    grad = ["-fslgrad", str(small_64d["bvecs_file"]), str(small_64d["bval"])]
    for command in (["dwi2response", "tournier", str(small_64d["dwi"]), "response.txt", *grad, "-number", "50",
                     "-scratch", str(d)],
                    ["dwi2fod", "csd", str(small_64d["dwi"]), "response.txt", "fod.mif", *grad, "-lmax", "8"],
                    ["mrconvert", "fod.mif", "fod.nii"]):
        run = subprocess.run([*command, "-quiet", "-nthreads", "1"], cwd=d, capture_output=True, text=True,
                             timeout=MRTRIX_TIMEOUT)
        assert run.returncode == 0, (command, run.stderr)
    return d / "fod.mif", nib.load(d / "fod.nii")


def physical_lps(affine, voxels):
    return (RAS_TO_LPS @ (affine[:3, :3] @ np.asarray(voxels, float).T + affine[:3, 3:4])).T


def straight_line(affine, seed, shape):
    grid = np.stack(np.meshgrid(*map(np.arange, shape), indexing="ij"), -1).reshape(-1, 3)
    return np.linalg.norm(physical_lps(affine, grid) - physical_lps(affine, [seed]), axis=1).reshape(shape)


def tool_map(path, basis, seed, out, *extra):
    run = subprocess.run([str(TOOL), "distance", str(path), "--fod-basis", basis, "--seed-voxel",
                          ",".join(map(str, seed)), "-o", str(out), "--quiet", *extra], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return nib.load(out)


SEED = (5, 5, 5)


def check_real_map(distance, affine, seed):
    assert distance.dtype == np.float32 and distance.shape == (10, 10, 10)
    assert np.isfinite(distance).all()
    assert distance[seed] == 0.0 and (distance > 0).sum() == distance.size - 1
    # F* >= |v|: no path is shorter than the straight line (float32 rounding).
    straight = straight_line(affine, seed, distance.shape)
    assert (distance >= straight * (1 - 1e-6)).all(), np.min(distance - straight)
    return distance / np.maximum(straight, 1e-9)


def test_dipy_fit_through_the_package_and_the_tool(tmp_path, small_64d, dipy_fit):
    affine = small_64d["affine"]
    image = stvd.fod_distance(dipy_fit, SEED, fod_basis="descoteaux07_legacy", affine=affine)
    distance = np.asanyarray(image.dataobj)
    assert np.allclose(image.affine, affine)
    ratio = check_real_map(distance, affine, SEED)
    # Measured: the map (STVD, the default) is 1.5 to 6.2 times the straight
    # distance (median 2.6; under Dijkstra 1.6 to 6.2, median 2.65).
    assert ratio[ratio > 0].min() >= 1.0
    path = tmp_path / "dipy_fod.nii.gz"
    nib.save(nib.Nifti1Image(dipy_fit.shm_coeff.astype(np.float32), affine), path)
    tool = np.asanyarray(tool_map(path, "descoteaux07_legacy", SEED, tmp_path / "tool.nii.gz").dataobj)
    assert tool.tobytes() == distance.tobytes()


def test_mrtrix_fit_through_the_package_and_the_tool(tmp_path, small_64d, mrtrix_fod):
    path, nifti = mrtrix_fod
    image = stvd.fod_distance(path, SEED, fod_basis="mrtrix3")
    distance = np.asanyarray(image.dataobj)
    ratio = check_real_map(distance, image.affine, SEED)
    # Measured (STVD): 1.27 to 5.1 times the straight distance (median 2.4).
    assert ratio[ratio > 0].min() >= 1.0
    # The tool on the .mif file and on MRtrix's own NIfTI conversion.
    tool = tool_map(path, "mrtrix3", SEED, tmp_path / "tool.nii.gz")
    assert np.asanyarray(tool.dataobj).tobytes() == distance.tobytes()
    assert np.allclose(tool.affine, image.affine)


OFFSETS = np.array([np.array(o) - 1 for o in np.ndindex(3, 3, 3) if o != (1, 1, 1)])


def voxel_to_lps(affine):
    return RAS_TO_LPS @ (affine[:3, :3] / np.linalg.norm(affine[:3, :3], axis=0))


def angle_between(a, b):
    return np.degrees(np.arccos(min(1.0, abs(float(np.dot(a, b))) / np.linalg.norm(a) / np.linalg.norm(b))))


def fod_peaks(coefficients, basis_type, legacy, to_lps):
    """The FOD's maxima (LPS) with at least half the largest's amplitude."""
    sphere = get_sphere("repulsion724").subdivide(1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        values = sh_to_sf(np.asarray(coefficients, float), sphere, sh_order=8, basis_type=basis_type, legacy=legacy)
    peaks, _, _ = peak_directions(values, sphere, relative_peak_threshold=0.5, min_separation_angle=25)
    return peaks @ to_lps.T


def cheapest_step(dipy_fit, affine, seed, steps_lps, method):
    """The 26-neighbour step (LPS) to which the map from seed is smallest
    per millimetre."""
    distance = np.asanyarray(stvd.fod_distance(dipy_fit, seed, fod_basis="descoteaux07_legacy", affine=affine,
                                               method=method).dataobj)
    per_mm = np.array([distance[tuple(np.add(seed, o))] for o in OFFSETS]) / np.linalg.norm(steps_lps, axis=1)
    return steps_lps[np.argmin(per_mm)]


def test_the_maps_cheapest_step_follows_the_fods_peaks(small_64d, dipy_fit, mrtrix_fod):
    affine = small_64d["affine"]
    _, nifti = mrtrix_fod
    mr_coefficients = np.asanyarray(nifti.dataobj)
    steps_lps = OFFSETS @ (RAS_TO_LPS @ affine[:3, :3]).T
    interior = [tuple(np.add(v, 1)) for v in np.ndindex(8, 8, 8)]
    peaks = {v: fod_peaks(dipy_fit.shm_coeff[v], "descoteaux07", True, voxel_to_lps(affine)) for v in interior}

    # DIPY's and MRtrix3's fits of the same voxel (the MRtrix image on its
    # own grid, found by physical position) have the same largest peak in
    # LPS, each fit in its own frame (voxel, scanner) carried by stvd's
    # conventions: measured at most 9.8 degrees over these 8 voxels, median 2.5.
    rng = np.random.default_rng(3)
    seeds = [tuple(v) for v in rng.integers(1, 9, size=(8, 3))]
    between = []
    for seed in seeds:
        mr_voxel = np.rint(np.linalg.solve(nifti.affine, affine @ np.r_[seed, 1.0])[:3]).astype(int)
        mrtrix_peaks = fod_peaks(mr_coefficients[tuple(mr_voxel)], "tournier07", False, RAS_TO_LPS)
        between.append(min(angle_between(peaks[seed][0], p) for p in mrtrix_peaks))
    assert max(between) <= 10.0 and np.median(between) <= 5.0, between

    # Anywhere: the cheapest step lies within 30 degrees of one of the FOD's
    # peaks (measured at most 28.3 over these 8 seeds, under STVD, the
    # default, and Dijkstra alike; the 26 directions are up to 27.6 degrees
    # from a direction on an isotropic grid, and a step's cost mixes the
    # norms of the voxels it passes).
    for method in ("stvd", "dijkstra"):
        for seed in seeds:
            cheapest = cheapest_step(dipy_fit, affine, seed, steps_lps, method)
            assert min(angle_between(cheapest, p) for p in peaks[seed]) <= 30.0, (method, seed)

    # Where the FOD has one peak (155 of the 512 inner voxels; every 8th of
    # them): the cheapest step is the stencil direction nearest to the peak,
    # or, where two are about as near, one a few degrees further.
    # Dijkstra (a step's cost the mean of its two voxels' norms): the
    # nearest at 18 of 20 seeds, 2.8 and 6.2 degrees further at the other two.
    # STVD (a step's cost sampled along it, each sample interpolating the
    # norms of the 8 voxels around it): the same at 19 of them; at the 20th,
    # (3, 2, 2), whose peak is more than 30 degrees from every peak of 21 of
    # its 26 neighbours, the cheapest step is 33.1 degrees further, towards
    # where its neighbours' norms lead.
    single = [v for v in interior if len(peaks[v]) == 1]

    def outlier(seed):
        """The seed's peak more than 30 degrees from every peak of at least 20 of its 26 neighbours."""
        around = [tuple(np.add(seed, o)) for o in OFFSETS]
        around_peaks = [peaks[v] if v in peaks else fod_peaks(dipy_fit.shm_coeff[v], "descoteaux07", True,
                                                              voxel_to_lps(affine)) for v in around]
        apart = [min(angle_between(peaks[seed][0], p) for p in ps) > 30.0 for ps in around_peaks]
        return sum(apart) >= 20

    for method, nearest_at, outliers in (("dijkstra", 18, 0), ("stvd", 17, 1)):
        excess = {}
        for seed in single[::8]:
            cheapest = cheapest_step(dipy_fit, affine, seed, steps_lps, method)
            nearest = min(angle_between(s, peaks[seed][0]) for s in steps_lps)
            excess[seed] = angle_between(cheapest, peaks[seed][0]) - nearest
        assert sum(e < 1e-6 for e in excess.values()) >= nearest_at, (method, excess)
        beyond = [seed for seed, e in excess.items() if e > 6.5]
        assert len(beyond) <= outliers and all(outlier(seed) and excess[seed] <= 33.5 for seed in beyond), \
            (method, excess)
