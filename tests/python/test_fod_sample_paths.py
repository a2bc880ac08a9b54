"""Corticospinal and callosal paths through the centrum semiovale of the
real-brain FOD slab (sample_data/fod_philips_biobank), under the tensors
(`stvd path` with its default method, on sample_data/dti_philips_biobank)
and under the FOD (`--fod-basis mrtrix3`); docs/fod.md, "Real data",
"Paths through the crossing".

The runs are scripts/fod_crossing_qc.sh's (the demo's step: `stvd path
--report` per run and the index of the pages), which the test runs. Both
metrics run in the same box around the crossings (a mask: the slab's
mask inside slab voxels i 30..81, j 44..61, all 12 slices), so that the
FOD's table stays small. The end points were chosen on the FOD's peaks
(DIPY's peak_directions on the shipped lmax-4 coefficients, in the scanner's
RAS frame, the bundle's direction within 30 degrees of a peak): the
crossings are the voxels whose FOD has both a left-right and an
inferior-superior peak, at slab slices 4 to 8 (z 74 to 82 mm RAS), i 65..70
(left) and 38..43 (right). Each corticospinal path runs from a voxel with
an inferior-superior peak on slab slice 1 below a crossing to one on slice
10 above it (z 87 mm; the slab ends at 88 mm: the vertex is not in it);
the callosal path from the lateral left-right voxels beyond the left
crossing (i 78) to those beyond the right one (i 32), on slab slice 6
through the body of the corpus callosum.

What is held, with the measured figures as bounds: the paths cross; the FOD
paths keep within a voxel of their bundle's FOD peaks; the callosal tensor
path cuts across (straight through voxels with no left-right peak) where
the FOD path keeps to them; the corticospinal tensor paths do not cut
across on this data (12 directions at b = 1000), and the test says so
instead of inventing a difference."""

import json
import os
import pathlib
import subprocess
import sys
import warnings

import nibabel as nib
import numpy as np
import pytest
from scipy import ndimage

from conftest import DIPY_5D, SAMPLE, TOOL
from test_pages import Elements, require_safe_page

FOD_DIR = SAMPLE.parent / "fod_philips_biobank"
FOD = FOD_DIR / "fod_csd_lmax4_slab.nii.gz"
FOD_MASK = FOD_DIR / "fod_mask_slab.nii.gz"
FIRST_SLICE = 10
SCRIPT = pathlib.Path(__file__).resolve().parents[2] / "scripts" / "fod_crossing_qc.sh"
# The box around both crossings on the slab's grid (i, j, k ranges).
BOX = (slice(30, 82), slice(44, 62), slice(0, 12))
# Slab voxels (k on the slab: the DTI's k - 10).
PATHS = {
    "CST_L": ((67, 54, 1), (68, 53, 10)),
    "CST_R": ((41, 54, 1), (42, 52, 10)),
    "CC": ((78, 54, 6), (32, 54, 6)),
}
BUNDLE_AXIS = {"CST": np.array([0.0, 0.0, 1.0]), "CC": np.array([1.0, 0.0, 0.0])}  # scanner RAS
WITHIN = np.cos(np.radians(30.0))
CHORD_MM = 4.0  # a path's local direction: the chord from 4 mm before to 4 mm after


def bundle_of(name):
    return "CC" if name == "CC" else "CST"


@pytest.fixture(scope="module")
def qc(tmp_path_factory):
    """The folder scripts/fod_crossing_qc.sh wrote: the box masks, the four
    runs' paths and pages, and their index. It runs as a user's shared
    folder may have it: a link planted under a mask's name, pointing outside,
    and a spy numpy module on PYTHONPATH (test_the_script_runs_no_planted_
    module_and_writes_through_no_link checks that neither took effect)."""
    base = tmp_path_factory.mktemp("fod_crossing")
    folder = base / "qc"
    folder.mkdir()
    (folder / "box_mask_slab.nii.gz").symlink_to(base / "victim.nii.gz")
    planted = base / "planted"
    planted.mkdir()
    (planted / "numpy.py").write_text(f"open({str(base / 'spy_ran')!r}, 'w').close()\n")
    environment = dict(os.environ, STVD_EXECUTABLE=str(TOOL), STVD_PYTHON=sys.executable, PYTHONPATH=str(planted))
    run = subprocess.run(["bash", str(SCRIPT), str(folder)], capture_output=True, text=True, env=environment,
                         timeout=600)
    assert run.returncode == 0, run.stderr
    return folder


def test_the_script_runs_no_planted_module_and_writes_through_no_link(qc):
    base = qc.parent
    assert not (base / "spy_ran").exists()
    assert not (base / "victim.nii.gz").exists()
    mask = qc / "box_mask_slab.nii.gz"
    assert mask.is_file() and not mask.is_symlink()
    assert not list(qc.glob(".stvd-*")), "a staged mask was left behind"


@pytest.fixture(scope="module")
def runs(qc):
    """The six paths (tensor and FOD per path) as (N, 3) RAS arrays, the box
    mask on the slab's grid and the slab's affine."""
    box_image = nib.load(qc / "box_mask_slab.nii.gz")
    box = np.asanyarray(box_image.dataobj) > 0
    expected = np.zeros(box.shape, bool)
    expected[BOX] = True
    assert np.array_equal(box, expected & (np.asanyarray(nib.load(FOD_MASK).dataobj) > 0))
    paths = {}
    for kind in ("tensor", "fod"):
        cst = nib.streamlines.load(qc / f"cst_{kind}.tck").streamlines
        cc = nib.streamlines.load(qc / f"cc_{kind}.tck").streamlines
        assert len(cst) == 2 and len(cc) == 1
        for name, points in (("CST_L", cst[0]), ("CST_R", cst[1]), ("CC", cc[0])):
            paths[name, kind] = np.asarray(points, float)
    # Each path runs from its seed to its target (voxel centres on the slab).
    for (name, kind), points in paths.items():
        for end, voxel in zip((points[0], points[-1]), PATHS[name]):
            centre = box_image.affine @ np.r_[voxel, 1.0]
            assert np.linalg.norm(end - centre[:3]) < 1e-3, (name, kind, end, voxel)
    return paths, box, box_image.affine


@pytest.fixture(scope="module")
def bundles(runs):
    """Per bundle, the box voxels where its direction (within 30 degrees) is
    an FOD peak, and those where it is the tensor's principal direction
    (FA >= 0.2)."""
    from dipy.data import get_sphere
    from dipy.direction.peaks import peak_directions
    from dipy.reconst.shm import sh_to_sf

    _, box, _ = runs
    coefficients = np.asanyarray(nib.load(FOD).dataobj)
    sphere = get_sphere("repulsion724")  # directions in the scanner's RAS frame: MRtrix3's
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        amplitudes = sh_to_sf(coefficients[box].astype(float), sphere, sh_order=4, basis_type="tournier07",
                              legacy=False)
    fod = {b: np.zeros(box.shape, bool) for b in BUNDLE_AXIS}
    for n, voxel in enumerate(np.argwhere(box)):
        peaks, _, _ = peak_directions(amplitudes[n], sphere, relative_peak_threshold=0.5, min_separation_angle=25)
        for b, axis in BUNDLE_AXIS.items():
            fod[b][tuple(voxel)] = len(peaks) > 0 and bool((np.abs(peaks @ axis) >= WITHIN).any())
    image = nib.load(DIPY_5D)
    t = np.asanyarray(image.dataobj)[:, :, FIRST_SLICE:FIRST_SLICE + box.shape[2], 0, :].astype(float)
    d = np.stack([t[..., 0], t[..., 1], t[..., 3], t[..., 1], t[..., 2], t[..., 4], t[..., 3], t[..., 4],
                  t[..., 5]], -1).reshape(t.shape[:3] + (3, 3))
    values, vectors = np.linalg.eigh(d)
    axes = image.affine[:3, :3] / np.linalg.norm(image.affine[:3, :3], axis=0)  # voxel frame to RAS
    v1 = vectors[..., :, 2] @ axes.T
    md = values.mean(-1)
    fa = np.sqrt(1.5 * ((values - md[..., None]) ** 2).sum(-1) / np.maximum((values ** 2).sum(-1), 1e-30))
    tensor = {b: box & (np.abs(v1 @ axis) >= WITHIN) & (fa >= 0.2) for b, axis in BUNDLE_AXIS.items()}
    return {"fod": fod, "tensor": tensor}


def along_fraction(points, axis):
    """The fraction of the path's length whose local direction (the chord over
    CHORD_MM either side) lies within 30 degrees of the axis."""
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    arc = np.r_[0.0, np.cumsum(steps)]
    middle = (arc[:-1] + arc[1:]) / 2

    def at(s):
        return np.stack([np.interp(s, arc, points[:, c]) for c in range(3)], -1)

    chords = at(middle + CHORD_MM) - at(middle - CHORD_MM)
    along = np.abs(chords @ axis) >= WITHIN * np.linalg.norm(chords, axis=1)
    return steps[along].sum() / arc[-1]


def measure(runs, bundles):
    paths, box, affine = runs
    zooms = np.linalg.norm(affine[:3, :3], axis=0)
    to_voxel = np.linalg.inv(affine)
    figures = {}
    for (name, kind), points in paths.items():
        b = bundle_of(name)
        voxels = np.rint(points @ to_voxel[:3, :3].T + to_voxel[:3, 3]).astype(int)
        row = {"length": float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum()),
               "straight": float(np.linalg.norm(points[-1] - points[0])),
               "along": along_fraction(points, BUNDLE_AXIS[b])}
        crossing = bundles["fod"]["CST"] & bundles["fod"]["CC"]
        row["crossing_voxels"] = float(len({tuple(v) for v in voxels if crossing[tuple(v)]}))
        for mask_kind in ("fod", "tensor"):
            mask = bundles[mask_kind][b]
            stray = ndimage.distance_transform_edt(~mask, sampling=zooms)[tuple(voxels.T)]
            row[f"in_{mask_kind}"] = float(mask[tuple(voxels.T)].mean())
            row[f"stray_{mask_kind}"] = float(stray.max())
        figures[name, kind] = row
    for (name, kind), row in sorted(figures.items()):
        print(name, kind, {k: round(v, 2) for k, v in row.items()})
    return figures


def gap(a, b):
    """The smallest distance between two polylines' points (mm)."""
    return float(np.min(np.linalg.norm(a[:, None] - b[None], axis=-1)))


def test_paths_through_the_crossing(runs, bundles):
    """Measured (docs/fod.md, "Paths through the crossing"); the bounds are
    the measured figures rounded outwards."""
    figures = measure(runs, bundles)
    paths = runs[0]
    fod = {name: figures[name, "fod"] for name in PATHS}
    tensor = {name: figures[name, "tensor"] for name in PATHS}
    for (name, kind), row in figures.items():
        assert row["length"] >= row["straight"] * (1 - 1e-6), (name, kind, row)
    # The paths cross in the centrum semiovale: the callosal path passes
    # voxels whose FOD has both a left-right and an inferior-superior peak
    # (measured 9 under the FOD, 5 under the tensors), and each
    # corticospinal path comes within one voxel of the callosal path of its
    # metric (measured 2.0 and 2.0 mm under the FOD, 2.6 and 3.8 under the
    # tensors).
    assert fod["CC"]["crossing_voxels"] >= 8 and tensor["CC"]["crossing_voxels"] >= 4
    for name in ("CST_L", "CST_R"):
        assert gap(paths[name, "fod"], paths["CC", "fod"]) <= 2.0 + 1e-3, name
        assert gap(paths[name, "tensor"], paths["CC", "tensor"]) <= 4.0, name
    # The FOD paths keep to their bundles through the crossing: every point
    # within one voxel's diagonal (2.83 mm) of a voxel where the bundle's
    # direction is an FOD peak, and most points in such voxels (measured
    # 0.80, 0.90, 0.79 of the points of CST_L, CST_R, CC).
    for name, row in fod.items():
        assert row["stray_fod"] <= 2 * 2 ** 0.5 + 1e-3, (name, row)
        assert row["in_fod"] >= 0.75, (name, row)
    # Where the tensor path cuts across: the callosal one. It runs straight
    # left-right (96.6 mm for 92.0 straight) through voxels without a
    # left-right FOD peak (the cingulum's and the corona radiata's beside
    # the callosum): half its points (0.50) lie in voxels with that peak,
    # against 0.79 for the FOD path, which bends to keep to them (105.1 mm),
    # and it strays further from them (3.46 mm against 2.83).
    assert fod["CC"]["in_fod"] - tensor["CC"]["in_fod"] >= 0.2, (fod["CC"], tensor["CC"])
    assert tensor["CC"]["stray_fod"] > fod["CC"]["stray_fod"] + 0.3
    # By the tensors' principal directions neither callosal path keeps to
    # L-R voxels (0.34 and 0.38 of their points): in the crossings the
    # tensors point S-I, and only the FOD has an L-R corridor through them.
    assert tensor["CC"]["in_tensor"] <= 0.45 and fod["CC"]["in_tensor"] <= 0.45, (tensor["CC"], fod["CC"])
    # The corticospinal tensor paths do not cut across on this data (12
    # directions at b = 1000): they keep to the FOD's inferior-superior
    # voxels about as well (0.79 and 0.75 of their points, within 2.0 mm),
    # and, smooth where the FOD's paths are chains of the 26 neighbour
    # directions, run along S-I over all their length (FOD: 1.00, 0.83).
    for name in ("CST_L", "CST_R"):
        assert tensor[name]["in_fod"] >= 0.7 and tensor[name]["stray_fod"] <= 2.0 + 1e-3, (name, tensor[name])
    for name, row in tensor.items():
        assert row["along"] >= 0.95, (name, row)
    assert fod["CST_L"]["along"] >= 0.95 and fod["CST_R"]["along"] >= 0.8 and fod["CC"]["along"] >= 0.65, fod
    # Lengths over the straight distance: the FOD's discrete paths 1.08,
    # 1.09, 1.14; the tensors' refined ones 1.007, 1.017, 1.049.
    for name, row in fod.items():
        assert row["length"] <= 1.16 * row["straight"], (name, row)
    for name, row in tensor.items():
        assert row["length"] <= 1.06 * row["straight"], (name, row)


def summary_of(page):
    parsed = Elements(page.read_text())
    bodies = [body for attributes, body in parsed.scripts if attributes.get("id") == "stvd-report-summary"]
    assert len(bodies) == 1, page
    return json.loads(bodies[0])


def test_the_qc_pages_show_tensor_and_fod_paths_side_by_side(qc):
    """scripts/fod_crossing_qc.sh (the demo's step): four pages, each the
    run's own (the FOD pages state the FOD metric, the tensor pages the
    tensors), and an index that lists and links all four, in pairs
    (cc_fod, cc_tensor, cst_fod, cst_tensor); every page and the index
    follow the page rules (docs/reliability.md, "Security")."""
    pages = {name: qc / f"{name}.html" for name in ("cc_fod", "cc_tensor", "cst_fod", "cst_tensor")}
    for name, page in pages.items():
        text = page.read_text()
        require_safe_page(text)
        summary = summary_of(page)
        assert summary["status"] == "ok" and summary["kind"] == "path", (name, summary)
        assert summary["figures"]["paths"] == (2 if name.startswith("cst") else 1), (name, summary["figures"])
        assert summary["figures"]["domain_voxels"] == 11232, (name, summary["figures"])
        assert summary["subject"] == name  # --subject
        if name.endswith("fod"):
            assert "FOD image read in the basis tournier07" in text and "distance map over GFA" in text
        else:
            assert "FOD image" not in text and "distance map over FA" in text
    index = (qc / "index.html").read_text()
    links, sources = require_safe_page(index)
    assert links == [f"./{name}.html" for name in sorted(pages) for _ in range(2)], links  # name and thumbnail
    assert len(sources) == 4


def test_the_figure_of_the_docs_is_made_from_the_pages(qc, tmp_path):
    """scripts/fod_crossing_figure.py: the four coronal panels, cut to the
    box and the slab's 12 slices (3.5 pixels per voxel, drawn 3 times as
    large), one above the other."""
    from PIL import Image

    figure = tmp_path / "coronal.png"
    run = subprocess.run([sys.executable, str(SCRIPT.parent / "fod_crossing_figure.py"), str(qc), str(figure)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    width, height = Image.open(figure).size
    assert height == 8 + 4 * (42 * 3 + 8) and width == 110 + 194 * 3 + 8, (width, height)
