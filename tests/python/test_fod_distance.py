"""stvd.fod_distance (docs/python.md, "FOD images"; docs/fod.md): a crossing
of two bundles simulated by DIPY's multi_tensor and fitted by DIPY's CSD,
given to the package as the fit object, as an array with its affine, as a
NiBabel image and as a file: the seed's own bundle's far end at the bundle's
length, the same map as `stvd distance FOD --fod-basis` bit for bit, the same
distances under a rotated and flipped affine (an isometry of the phantom),
and the refusals of a wrong basis, of tensors given as an FOD, of a bare
array or fit without its basis; STVD and Lanthier's method (method=) give
the tool's maps too, STVD being the default (as for tensors) and Dijkstra
given by method='dijkstra'."""

import os
import pathlib
import subprocess

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import TOOL

from fod_phantoms import crossing_fit, write_mif

BASIS = "descoteaux07_legacy"  # DIPY 1.6's CSD fits (docs/fod.md, "The bases")
SPACING = 2.0


@pytest.fixture(scope="module")
def crossing():
    fit, axes, _ = crossing_fit(90)
    return fit, axes


def identity_affine():
    return np.diag([SPACING, SPACING, SPACING, 1.0])


def rotated_flipped_affine():
    """2 mm voxels along axes rotated 35 degrees about (1, 2, 2)/3, the first
    one flipped, and shifted: an isometry of the identity case's space."""
    angle = np.radians(35.0)
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    affine = np.eye(4)
    affine[:3, :3] = rotation @ np.diag([-SPACING, SPACING, SPACING])
    affine[:3, 3] = [12.0, -30.0, 4.0]
    return affine


def values(image):
    return np.asanyarray(image.dataobj)


def test_the_fit_reaches_its_own_bundles_far_end_at_the_bundles_length(crossing):
    fit, axes = crossing
    image = stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine())
    distance = values(image)
    assert distance.dtype == np.float32 and distance.shape == (21, 21, 3)
    assert np.allclose(image.affine, identity_affine())
    # 20 voxels of 2 mm along the bundle, straight through the crossing.
    assert distance[20, 10, 1] == pytest.approx(40.0, rel=0.005)
    # The other bundle's far end: along the seed's bundle to the crossing,
    # then along the other, the two legs' length.
    assert distance[10, 20, 1] == pytest.approx(2 * SPACING * 10, rel=0.02)
    # Across the bundles' gap (zero coefficients: the floor, 10 per mm) a
    # corner costs more than the way along the bundles.
    assert distance[20, 20, 1] > distance[10, 20, 1] + 5 * SPACING


def test_the_package_map_is_the_tools_bit_for_bit(tmp_path, crossing):
    fit, _ = crossing
    path = tmp_path / "crossing_fod.nii.gz"
    nib.save(nib.Nifti1Image(fit.shm_coeff.astype(np.float32), identity_affine()), path)
    out = tmp_path / "tool_distance.nii.gz"
    run = subprocess.run([str(TOOL), "distance", str(path), "--fod-basis", BASIS, "--seed-voxel", "0,10,1",
                          "-o", str(out), "--threads", "2", "--quiet"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    tool = np.asanyarray(nib.load(out).dataobj)
    # The file, the NiBabel image, the array and the fit: the tool's bytes.
    for given, affine in ((path, None), (nib.load(path), None), (fit.shm_coeff, identity_affine()),
                          (fit, identity_affine())):
        mine = values(stvd.fod_distance(given, (0, 10, 1), fod_basis=BASIS, affine=affine, threads=1))
        assert mine.dtype == tool.dtype and mine.tobytes() == tool.tobytes(), type(given)


def test_stvd_and_lanthier_give_the_tools_maps_bit_for_bit(tmp_path, crossing):
    """method='stvd' (the default) and method='lanthier' run on the segment
    norm (docs/fod.md, "STVD and Lanthier") as `stvd distance --method`: the
    same bytes, and the seed's own bundle's far end at the bundle's length;
    method='dijkstra' runs Dijkstra's 26-direction table instead."""
    fit, _ = crossing
    path = tmp_path / "crossing_fod.nii.gz"
    nib.save(nib.Nifti1Image(fit.shm_coeff.astype(np.float32), identity_affine()), path)
    dijkstra = values(stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(),
                                        method="dijkstra"))
    assert dijkstra[20, 10, 1] == pytest.approx(40.0, rel=0.005)
    by_default = values(stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine()))
    for method, extra, keywords in (("stvd", [], {}), ("dijkstra", [], {}),
                                    ("lanthier", ["--steiner", "2"], {"steiner": 2})):
        out = tmp_path / f"tool_{method}.nii.gz"
        run = subprocess.run([str(TOOL), "distance", str(path), "--fod-basis", BASIS, "--seed-voxel", "0,10,1",
                              "--method", method, *extra, "-o", str(out), "--quiet"], capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        tool = np.asanyarray(nib.load(out).dataobj)
        mine = values(stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), method=method,
                                        **keywords))
        assert mine.dtype == tool.dtype and mine.tobytes() == tool.tobytes(), method
        assert mine[20, 10, 1] == pytest.approx(40.0, rel=0.005), method
        # The default is STVD's map; the others are not Dijkstra's: the method was run.
        assert np.array_equal(mine, by_default) == (method == "stvd"), method
        assert np.array_equal(mine, dijkstra) == (method == "dijkstra"), method


def test_a_rotated_and_flipped_affine_gives_the_same_distances(crossing):
    # DIPY's coefficients are in the voxel frame: under a rotated, flipped
    # affine the phantom is the same one moved rigidly in physical space,
    # and so are its distances, voxel by voxel; the seed as a world point.
    fit, _ = crossing
    coefficients = fit.shm_coeff.astype(np.float32)
    straight = nib.Nifti1Image(coefficients, identity_affine())
    rotated = nib.Nifti1Image(coefficients, rotated_flipped_affine())
    a = values(stvd.fod_distance(straight, (0, 10, 1), fod_basis=BASIS))
    seed_point = (rotated.affine @ np.array([0.0, 10.0, 1.0, 1.0]))[:3]
    b_image = stvd.fod_distance(rotated, seed_points=seed_point, fod_basis=BASIS)
    b = values(b_image)
    assert np.allclose(b_image.affine, rotated_flipped_affine(), atol=1e-5)
    assert np.all(np.isfinite(a)) and np.all(np.isfinite(b))
    # Along the seed's bundle F* is F at the refined maxima, whatever the
    # grid's orientation: the same distances, 2 mm a voxel.
    assert np.allclose(b[:, 10, 1], a[:, 10, 1], rtol=1e-5, atol=1e-5)
    assert b[20, 10, 1] == pytest.approx(40.0, rel=0.005)
    assert b[10, 20, 1] == pytest.approx(a[10, 20, 1], rel=0.005)
    # Elsewhere F* is the hull of the FOD's ball sampled along a fixed
    # icosphere in LPS and the grid's own 26 directions (docs/fod.md), so
    # it moves with the grid only up to the hull's excess between sampling
    # directions (at most 8.2 % on such crossings): measured 5.6 % at most,
    # 0.6 % on average. A frame read wrongly costs 3.5 times as much
    # (docs/fod.md, "Propagation").
    relative = np.abs(a - b) / np.maximum(a, 1e-9)
    assert relative.max() < 0.082 and relative.mean() < 0.01, (relative.max(), relative.mean())




def test_an_mrtrix_file_gives_the_same_map_on_its_own_grid(tmp_path, crossing):
    # The same coefficients as a .mif file (the frame stated: a .mif is in
    # the scanner frame unless told) under the rotated, flipped affine: the
    # NIfTI image's map, and a NiBabel image of the file's grid, which
    # NiBabel cannot read itself.
    fit, _ = crossing
    coefficients = fit.shm_coeff.astype(np.float32)
    path = tmp_path / "crossing_fod.mif"
    write_mif(path, coefficients, rotated_flipped_affine())
    from_mif = stvd.fod_distance(path, (0, 10, 1), fod_basis=BASIS, fod_frame="voxel")
    from_nifti = stvd.fod_distance(nib.Nifti1Image(coefficients, rotated_flipped_affine()), (0, 10, 1),
                                   fod_basis=BASIS)
    assert values(from_mif).tobytes() == values(from_nifti).tobytes()
    assert np.allclose(from_mif.affine, rotated_flipped_affine(), atol=1e-6)


def test_bad_input_is_refused_in_one_clear_line(tmp_path, crossing):
    fit, _ = crossing
    coefficients = fit.shm_coeff.astype(np.float32)

    def message(*args, **kwargs):
        with pytest.raises(ValueError) as error:
            stvd.fod_distance(*args, **kwargs)
        text = str(error.value)
        assert "\n" not in text, text
        return text

    # A basis that does not exist: the accepted names.
    text = message(coefficients, (0, 10, 1), fod_basis="descoteaux", affine=identity_affine())
    assert "fod_basis" in text and "descoteaux07_legacy" in text and "mrtrix3" in text, text
    # A bare array, or a DIPY fit (which records no basis), without a basis.
    assert "fod_basis" in message(coefficients, (0, 10, 1), affine=identity_affine())
    assert "descoteaux07_legacy" in message(fit, (0, 10, 1), affine=identity_affine())
    path = tmp_path / "crossing_fod.nii.gz"
    nib.save(nib.Nifti1Image(coefficients, identity_affine()), path)
    assert "fod_basis" in message(path, (0, 10, 1))
    # A tensor volume given as an FOD: six values per voxel, or 3x3 matrices.
    tensors = np.zeros((21, 21, 3, 6), np.float32)
    tensors[..., 0] = tensors[..., 2] = tensors[..., 5] = 1e-3
    text = message(tensors, (0, 10, 1), fod_basis=BASIS, affine=identity_affine())
    assert "six values" in text and "stvd.distance" in text, text
    text = message(np.zeros((21, 21, 3, 3, 3), np.float32), (0, 10, 1), fod_basis=BASIS, affine=identity_affine())
    assert "(X, Y, Z, N)" in text, text
    # An array without its affine; a count of coefficients no lmax has.
    assert "affine=" in message(coefficients, (0, 10, 1), fod_basis=BASIS)
    assert "44" in message(coefficients[..., :44], (0, 10, 1), fod_basis=BASIS, affine=identity_affine())
    # Lanthier's method needs its M, as the tool's --steiner; k= goes with STVD
    # (the default: k= alone is taken), not with Dijkstra.
    text = message(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), method="lanthier")
    assert "steiner=" in text, text
    text = message(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), method="dijkstra", k=8)
    assert "k" in text and "stvd" in text, text
    k8 = values(stvd.fod_distance(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), k=8))
    assert k8[20, 10, 1] == pytest.approx(40.0, rel=0.005)
    # The cost's keywords are checked by their declarations.
    assert "fod_floor" in message(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), fod_floor=0)
    assert "fod_power" in message(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), fod_power=9)
    assert "fod_frame" in message(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(),
                                  fod_frame="world-ish")


def test_the_fod_keywords_are_the_declared_ones():
    import inspect

    parameters = inspect.signature(stvd.fod_distance).parameters
    declared = [d for d in stvd._core.option_declarations() if "fod-distance" in d["keyword_commands"]]
    assert {d["keyword"] for d in declared} == {"fod_basis", "fod_frame", "fod_floor", "fod_power"}
    for d in declared:
        assert d["keyword"] in parameters and parameters[d["keyword"]].default is None
        if d["defaults"].get("distance") is not None:
            assert getattr(stvd.defaults, d["keyword"]) == d["defaults"]["distance"]
    assert stvd.defaults.fod_floor == 0.1 and stvd.defaults.fod_power == 1.0


def test_a_mask_and_a_higher_floor(crossing):
    fit, _ = crossing
    coefficients = fit.shm_coeff.astype(np.float32)
    # Outside the mask of bundle 0 nothing is reached.
    mask = np.zeros((21, 21, 3), np.uint8)
    mask[:, 8:13, :] = 1
    d = values(stvd.fod_distance(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), mask=mask,
                                 unreachable_value=-1))
    assert d[10, 20, 1] == -1 and d[20, 10, 1] == pytest.approx(40.0, rel=0.005)
    # A higher floor makes leaving the bundles cheaper.
    low = values(stvd.fod_distance(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine()))
    high = values(stvd.fod_distance(coefficients, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(),
                                    fod_floor=0.5))
    assert high[20, 20, 1] < low[20, 20, 1]


def test_progress_is_relayed_and_a_cancel_gives_no_map(crossing):
    fit, _ = crossing
    calls = []
    image = stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(),
                              progress=lambda *report: calls.append(report))
    # The propagation's reports: at the start and at the end, every one of
    # the 1,323 voxels finalised.
    assert calls[0][:2] == (0, 21 * 21 * 3) and calls[-1][0] == 21 * 21 * 3
    assert [c[0] for c in calls] == sorted(c[0] for c in calls)
    assert all(0 <= c[2] <= np.max(values(image)) for c in calls)
    with pytest.raises(RuntimeError, match="cancelled by the progress function"):
        stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(),
                          progress=lambda *report: False)

    class Stop(Exception):
        pass

    def fail(*report):
        raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), progress=fail)


def test_the_table_reports_to_the_progress_function_and_false_stops_it(crossing):
    # The FOD table reports as the run's first reports, no voxel final yet:
    # at its start and at its end, then the propagation's first report.
    fit, _ = crossing
    calls = []
    stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), threads=1,
                      progress=lambda *report: calls.append(report))
    before = [c for c in calls if c[0] == 0]
    assert len(before) >= 3 and all(c == (0, 21 * 21 * 3, 0.0) for c in before)
    # False from the table's last report at the latest: cancelled there,
    # no map, and the propagation never reported.
    seen = []

    def second_stops(*report):
        seen.append(report)
        return len(seen) < 2

    with pytest.raises(RuntimeError, match="during the FOD table: no map"):
        stvd.fod_distance(fit, (0, 10, 1), fod_basis=BASIS, affine=identity_affine(), threads=1,
                          progress=second_stops)
    assert seen == [(0, 21 * 21 * 3, 0.0)] * 2


def test_runs_in_threads_give_the_serial_maps(crossing):
    # The library works without the GIL: calls from several Python threads
    # run side by side, each with the map it has alone.
    import threading

    fit, _ = crossing
    seeds = [(0, 10, 1), (10, 0, 1), (20, 10, 2)]
    serial = [values(stvd.fod_distance(fit, s, fod_basis=BASIS, affine=identity_affine(), threads=1))
              for s in seeds]
    parallel = [None] * len(seeds)

    def compute(n):
        parallel[n] = values(stvd.fod_distance(fit, seeds[n], fod_basis=BASIS, affine=identity_affine(), threads=1))

    threads = [threading.Thread(target=compute, args=(n,)) for n in range(len(seeds))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(serial, parallel):
        assert a.tobytes() == b.tobytes()


DIPY_BASES = {"tournier07": ("tournier07", False), "tournier07_legacy": ("tournier07", True),
              "descoteaux07": ("descoteaux07", False), "descoteaux07_legacy": ("descoteaux07", True)}


@pytest.mark.parametrize("basis", sorted(DIPY_BASES))
def test_the_gfa_is_dipys_of_the_fod_sampled_on_a_dense_sphere(tmp_path, crossing, basis):
    """The GFA that FOD pages draw (stvd._core.fod_gfa: sqrt(1 - c00^2 / sum
    n_j c_j^2), n_j the squared norm of basis function j) is DIPY's `gfa` of
    the same FOD evaluated by DIPY in the same basis on a dense sphere
    (11,554 points): for coefficients with large m != 0 terms, where the
    legacy tournier07 normalisation (n_j = 1/2 for m != 0) matters, and for
    the crossing's CSD fit carried into each basis."""
    from dipy.data import get_sphere
    from dipy.reconst.odf import gfa as dipy_gfa
    from dipy.reconst.shm import sf_to_sh, sh_to_sf

    basis_type, legacy = DIPY_BASES[basis]
    sphere = get_sphere("repulsion724").subdivide(2)
    rng = np.random.default_rng(3)
    coefficients = rng.normal(0.0, 0.4, (4, 3, 2, 45))
    coefficients[..., 0] = rng.uniform(0.5, 2.0, (4, 3, 2))
    coefficients[0, 0, 0] = 0.0  # no FOD here: GFA 0 (DIPY: NaN)
    fit, _ = crossing
    signal = sh_to_sf(fit.shm_coeff[8:12, 8:11, 1:3], sphere, sh_order=8, basis_type="descoteaux07", legacy=True)
    coefficients[:, :, 1, :] = sf_to_sh(signal[:, :, 0], sphere, sh_order=8, basis_type=basis_type, legacy=legacy)
    path = tmp_path / f"{basis}.nii"
    nib.save(nib.Nifti1Image(coefficients.astype(np.float32), np.eye(4)), path)

    mine, _ = stvd._core.fod_gfa(str(path), basis)
    samples = sh_to_sf(coefficients.astype(np.float32).astype(np.float64), sphere, sh_order=8,
                       basis_type=basis_type, legacy=legacy)
    with np.errstate(invalid="ignore", divide="ignore"):
        theirs = dipy_gfa(samples)
    assert mine[0, 0, 0] == 0.0 and np.isnan(theirs[0, 0, 0])
    theirs[0, 0, 0] = 0.0
    error = np.abs(mine - theirs)
    assert error.max() < 2e-3, (basis, error.max())
    assert theirs[..., 1].min() > 0.3  # the crossing's voxels: an FOD with lobes, not noise
    if basis == "tournier07_legacy":
        # Its m != 0 functions are not normalised: taking them as if they
        # were would be far off.
        c = coefficients.astype(np.float64)
        orthonormal = np.sqrt(1 - c[..., 0] ** 2 / np.maximum((c ** 2).sum(-1), 1e-30))
        assert np.abs(orthonormal - theirs).max() > 20 * error.max()
