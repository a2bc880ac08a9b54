"""Synthetic crossings with ground truth (docs/fod.md, "Validation"): two
bundles cross at 30, 45, 60 and 90 degrees (DIPY's multi_tensor,
fod_phantoms.py), fitted by DIPY's CSD and by MRtrix3's `dwi2fod csd`, and
given to stvd.fod_distance, by its default method (STVD) and by Dijkstra's.
From a seed at one end of a bundle the map reaches the far end of the same
bundle along it, not along the other: the geodesic, traced back from the far
end by steepest descent on the map (over the 26-neighbourhood for Dijkstra,
whose paths are chains of neighbour steps; over the lattice of order 2, the
offsets up to 2 voxels that STVD's segment norm tabulates, for STVD), keeps
every point inside its own bundle, and inside the crossing its direction
(the chord over 3 steps either side) stays within a stated angle of the true
bundle direction. The angles are the ones measured per method, fitter and
crossing (docs/fod.md gives them), not loosened: at 30 degrees neither CSD
resolves the two fibres at b = 3000 (one lobe on the bisector, which the
test checks); Dijkstra's path of the oblique bundle then runs along the
other bundle through the crossing (a strict expected failure, which fails
the day the path keeps to its bundle), STVD's keeps to its own."""

import shutil
import warnings

import numpy as np
import pytest

import stvd
from dipy.data import get_sphere
from dipy.direction import peak_directions
from dipy.reconst.shm import sh_to_sf

from fod_phantoms import crossing_fit, mrtrix_crossing_fod

SPACING = 2.0
AFFINE = np.diag([SPACING, SPACING, SPACING, 1.0])
CENTRE = np.array([10.0, 10.0])
HALF_LENGTH = 10.0  # voxels from the centre to a bundle's end
WINDOW = 3  # steps either side of a path point for its direction

# Measured (docs/fod.md, "Validation"), bounds for both fitters: the
# largest angle (degrees) between the path's direction and its bundle's at
# a point of the crossing, and the largest ratio of the map's distance
# between the bundle's ends to their straight distance, per method,
# crossing angle and bundle (0: along the voxel axis i, 1: at the crossing
# angle to it). Dijkstra: bundles along a stencil direction (0, 45, 90
# degrees) are followed exactly; bundle 1 at 60 degrees lies between the
# 26-neighbour directions at 45 and 90 degrees: its path zig-zags on them
# (3.7 degrees from the axis over a 6-step chord) and, the lobes being
# narrow at b = 3000, its length is about twice the straight one
# (Dijkstra's metrication, not the FOD's). STVD: the same lengths along
# stencil directions (to 1e-5); bundle 1 at 60 degrees at 1.069 (DIPY) and
# 1.071 (MRtrix) times the straight length, its path 3.4 degrees from the
# axis (steps (1, 2), 63.4 degrees); at 30 degrees bundle 1 too (1.280 and
# 1.267, 3.4 degrees).
ANGLE_BOUND = {
    "dijkstra": {(30, 0): 0.5, (45, 0): 0.5, (45, 1): 0.5, (60, 0): 0.5, (60, 1): 4.0, (90, 0): 0.5, (90, 1): 0.5},
    "stvd": {(30, 0): 0.5, (30, 1): 4.0, (45, 0): 0.5, (45, 1): 0.5, (60, 0): 0.5, (60, 1): 4.0, (90, 0): 0.5,
             (90, 1): 0.5}}
LENGTH_RATIO_BOUND = {
    "dijkstra": {(30, 0): 1.17, (45, 0): 1.002, (45, 1): 1.003, (60, 0): 1.002, (60, 1): 2.15, (90, 0): 1.001,
                 (90, 1): 1.001},
    "stvd": {(30, 0): 1.17, (30, 1): 1.29, (45, 0): 1.002, (45, 1): 1.003, (60, 0): 1.002, (60, 1): 1.072,
             (90, 0): 1.001, (90, 1): 1.001}}
# The descent's reach (voxels): Dijkstra's paths are chains of neighbour
# steps; STVD's map falls along the lattice offsets of order 2 where a
# bundle lies between the neighbour directions (at 60 degrees a voxel can
# have no lower neighbour, its value coming along a (1, 2) step), and the
# crossing then holds fewer path points.
REACH = {"dijkstra": 1, "stvd": 2}
CROSSING_POINTS = {"dijkstra": 5, "stvd": 2}


def bundle_ends(axis):
    """The voxels (i, j, 1) at both ends of the bundle through the centre
    along axis: the centre -/+ 10 voxels along it, rounded."""
    ends = [np.rint(CENTRE + s * HALF_LENGTH * axis[:2]).astype(int) for s in (-1, 1)]
    return [(int(e[0]), int(e[1]), 1) for e in ends]


def steepest_descent(distance, start, reach=1):
    """The voxels from a seed (distance 0) to start, found backwards from
    start: at each voxel the voxel within `reach` voxels along each axis (1:
    the 26-neighbours) with the largest drop of the map per millimetre."""
    side = 2 * reach + 1
    offsets = [np.array(o) - reach for o in np.ndindex(side, side, side) if o != (reach,) * 3]
    path = [np.array(start)]
    while distance[tuple(path[-1])] > 0:
        here = path[-1]
        best, drop = None, 0.0
        for o in offsets:
            n = here + o
            if np.any(n < 0) or np.any(n >= distance.shape):
                continue
            d = (distance[tuple(here)] - distance[tuple(n)]) / (SPACING * np.linalg.norm(o))
            if d > drop:
                best, drop = n, d
        assert best is not None, f"no descent from {here}"
        path.append(best)
        assert len(path) <= distance.size
    return np.array(path[::-1])


def angles_in_crossing(path, axis, in_crossing):
    """The angle (degrees) between the axis and the path's direction at each
    of its voxels in the crossing: the chord from WINDOW steps before to
    WINDOW steps after (clamped to the path's ends)."""
    out = []
    for t, p in enumerate(path):
        if in_crossing(p[0], p[1]):
            chord = path[min(len(path) - 1, t + WINDOW)] - path[max(0, t - WINDOW)]
            cosine = abs(chord @ axis) / np.linalg.norm(chord)
            out.append(np.degrees(np.arccos(min(1.0, cosine))))
    return np.array(out)


_FITS = {}


@pytest.fixture
def fitted(tmp_path_factory):
    """fitted(fitter, angle): (the FOD as stvd.fod_distance takes it, its
    keywords, the coefficients and their DIPY basis, the axes, in_bundle),
    made once per fitter and angle."""

    def make(fitter, angle):
        if (fitter, angle) not in _FITS:
            if fitter == "dipy":
                fit, axes, in_bundle = crossing_fit(angle)
                _FITS[fitter, angle] = (fit, {"fod_basis": "descoteaux07_legacy", "affine": AFFINE},
                                        fit.shm_coeff, ("descoteaux07", True), axes, in_bundle)
            else:
                missing = [c for c in ("mrconvert", "dwi2response", "dwi2fod") if shutil.which(c) is None]
                if missing:
                    pytest.skip(f"MRtrix3 is not installed ({', '.join(missing)} not found): its CSD is not tested")
                directory = tmp_path_factory.mktemp(f"mrtrix{angle}")
                path, coefficients, axes, in_bundle = mrtrix_crossing_fod(angle, directory)
                _FITS[fitter, angle] = (path, {"fod_basis": "mrtrix3"}, coefficients, ("tournier07", False),
                                        axes, in_bundle)
        return _FITS[fitter, angle]

    return make


def angle_between(a, b):
    return np.degrees(np.arccos(min(1.0, abs(float(np.dot(a, b)) / np.linalg.norm(a) / np.linalg.norm(b)))))


FITTERS = ["dipy", "mrtrix"]
ANGLES = [30, 45, 60, 90]


@pytest.mark.parametrize("fitter", FITTERS)
@pytest.mark.parametrize("angle", ANGLES)
def test_the_fit_resolves_the_crossing_from_45_degrees(fitted, fitter, angle):
    # The FOD at the crossing's centre (its maxima over 11k directions): a
    # lobe per fibre from 45 degrees on, within 2 degrees of the truth
    # (measured: 0.5 to 1.6); at 30 degrees one lobe, within 1.5 degrees of
    # the bisector (measured: 0.9), for both fitters (b = 3000, lmax 8).
    _, _, coefficients, (basis_type, legacy), axes, _ = fitted(fitter, angle)
    sphere = get_sphere("repulsion724").subdivide(2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        values = sh_to_sf(np.asarray(coefficients[10, 10, 1], float), sphere, sh_order=8, basis_type=basis_type,
                          legacy=legacy)
    peaks, _, _ = peak_directions(values, sphere, relative_peak_threshold=0.3, min_separation_angle=15)
    if angle == 30:
        bisector = axes[0] + axes[1]
        assert len(peaks) == 1 and angle_between(peaks[0], bisector) < 1.5, peaks
    else:
        assert len(peaks) == 2, peaks
        for axis in axes:
                assert min(angle_between(p, axis) for p in peaks) < 2.0, (axis, peaks)


CASES = [pytest.param(m, f, a, b, id=f"{m}-{f}-{a}-bundle{b}",
                      marks=[pytest.mark.xfail(strict=True, reason="30 degrees is one lobe (not resolved): "
                                                                   "Dijkstra's path of the oblique bundle runs along "
                                                                   "the other one")]
                      if (m, a, b) == ("dijkstra", 30, 1) else [])
         for m in ("stvd", "dijkstra") for f in FITTERS for a in ANGLES for b in (0, 1)]


@pytest.mark.parametrize("method,fitter,angle,bundle", CASES)
def test_a_seed_reaches_its_own_bundles_far_end_along_it(fitted, method, fitter, angle, bundle):
    fod, keywords, _, _, axes, in_bundle = fitted(fitter, angle)
    seed, far = bundle_ends(axes[bundle])
    # STVD is the default; Dijkstra's figures are kept by asking for it.
    given = {"method": "dijkstra"} if method == "dijkstra" else {}
    distance = np.asanyarray(stvd.fod_distance(fod, seed, **given, **keywords).dataobj)
    path = steepest_descent(distance, far, REACH[method])
    assert tuple(path[0]) == seed

    # Every point of the geodesic in its own bundle (a slab, convex: its
    # voxels in it, so are the steps between them): not along the other.
    outside = [tuple(p) for p in path if not in_bundle(bundle, p[0], p[1])]
    assert not outside, (outside, path.tolist())

    # Inside the crossing, along the bundle.
    angles = angles_in_crossing(path, axes[bundle], lambda i, j: in_bundle(0, i, j) and in_bundle(1, i, j))
    assert len(angles) >= CROSSING_POINTS[method]
    assert angles.max() <= ANGLE_BOUND[method][angle, bundle], (angles, path.tolist())

    # Its length: at least the straight distance (F* >= |v|), and at most the
    # measured bound above it.
    straight = SPACING * np.linalg.norm(np.subtract(far, seed))
    assert straight * (1 - 1e-6) <= distance[far] <= LENGTH_RATIO_BOUND[method][angle, bundle] * straight
