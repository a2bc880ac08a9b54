"""stvd.fod_paths and stvd.fod_connectivity (docs/fod.md, "Paths and
connectivity"): on DIPY's CSD fit of a 90-degree crossing (fod_phantoms.py),
given as a file, a NiBabel image, an array with its affine and DIPY's fit
object, the package's paths are the tool's (`stvd path FOD --fod-basis`)
byte for byte in the file they save, and its connectivity the tool's table;
a path to its own bundle's far end stays on the bundle's axis and reports
its polyline's F*-length; STVD, tracing keywords and missing bases are
refused."""

import csv
import re
import subprocess

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import TOOL

from fod_phantoms import crossing_fit

BASIS = "descoteaux07_legacy"  # DIPY 1.6's CSD fits (docs/fod.md, "The bases")
SPACING = 2.0
AFFINE = np.diag([SPACING, SPACING, SPACING, 1.0])
SEED = (0, 10, 1)
TARGETS = [(20, 10, 1), (10, 20, 1)]  # the seed's own bundle's far end, the other bundle's


@pytest.fixture(scope="module")
def crossing(tmp_path_factory):
    fit, _, in_bundle = crossing_fit(90)
    path = tmp_path_factory.mktemp("fod") / "crossing_fod.nii.gz"
    nib.save(nib.Nifti1Image(fit.shm_coeff.astype(np.float32), AFFINE), path)
    return fit, path, in_bundle


def tool(*arguments):
    run = subprocess.run([str(TOOL), *map(str, arguments), "--quiet"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return run


def tsv_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f, delimiter="\t"))


def test_the_paths_are_the_tools_byte_for_byte(tmp_path, crossing):
    fit, path, _ = crossing
    out = tmp_path / "tool.tck"
    tool("path", path, "--fod-basis", BASIS, "--seed-voxel", ",".join(map(str, SEED)), *sum(
        (["--target-voxel", ",".join(map(str, t))] for t in TARGETS), []), "-o", out, "--threads", "2")
    table = tsv_rows(tmp_path / "tool.tsv")
    for n, (given, affine) in enumerate(((path, None), (nib.load(path), None), (fit.shm_coeff, AFFINE),
                                         (fit, AFFINE))):
        paths = stvd.fod_paths(given, SEED, TARGETS, fod_basis=BASIS, affine=affine, threads=1)
        mine = tmp_path / f"mine{n}.tck"
        paths.save(mine)
        assert mine.read_bytes() == out.read_bytes(), type(given)
        for p, row in enumerate(table):
            assert f"{paths.geodesic_mm[p]:.4f}" == row["geodesic_mm"]
            assert f"{paths.metric_length_mm[p]:.4f}" == row["metric_length_mm"]
            assert f"{paths.euclidean_mm[p]:.4f}" == row["euclidean_mm"]
            assert tuple(paths.seed_voxels[p]) == (int(row["seed_i"]), int(row["seed_j"]), int(row["seed_k"]))
            assert paths.discrete_points[p] == int(row["discrete_points"]) == len(paths[p])


def test_a_path_stays_on_its_bundle_and_reports_its_f_star_length(crossing):
    _, path, in_bundle = crossing
    paths = stvd.fod_paths(path, SEED, TARGETS, fod_basis=BASIS)
    to_index = np.linalg.inv(AFFINE)
    for p, target in enumerate(TARGETS):
        points = np.c_[paths[p], np.ones(len(paths[p]))] @ to_index.T
        assert np.allclose(points[0, :3], SEED) and np.allclose(points[-1, :3], target)
        for i, j, k, _ in points:
            if p == 0:  # straight through the crossing on the bundle's axis
                assert j == pytest.approx(10.0) and k == pytest.approx(1.0)
            else:  # along bundle 0, then bundle 1: never outside both
                assert in_bundle(0, i, j) or in_bundle(1, i, j)
        # The reported length is the polyline's F*-length (single precision).
        assert paths.metric_length_mm[p] == pytest.approx(paths.geodesic_mm[p], rel=1e-5)
        assert np.isnan(paths.mean_fa[p]) and paths.refine_iterations[p] == 0
    assert paths.geodesic_mm[0] == pytest.approx(40.0, rel=0.005)
    assert paths.geodesic_mm[1] == pytest.approx(40.0, rel=0.02)
    # A NiBabel tractogram of them, as for tensor paths.
    assert len(stvd.tractogram(paths).streamlines) == 2


def test_connectivity_is_the_tools_table(tmp_path, crossing):
    fit, path, _ = crossing
    labels = np.zeros((21, 21, 3), np.int16)
    for value, (i, j) in enumerate(((0, 10), (20, 10), (10, 0), (10, 20)), start=1):
        labels[i, j, 1] = value
    labels_path = tmp_path / "ends.nii.gz"
    nib.save(nib.Nifti1Image(labels, AFFINE), labels_path)
    tool("connectivity", path, "--fod-basis", BASIS, "--labels", labels_path, "-o", tmp_path / "c.tsv")
    rows = tsv_rows(tmp_path / "c.tsv")
    for threads in (1, 2):
        c = stvd.fod_connectivity(fit, labels, fod_basis=BASIS, affine=AFFINE, threads=threads,
                                  label_names={1: "a0", 2: "a1", 3: "b0", 4: "b1"})
        assert list(c.labels) == [1, 2, 3, 4] and c.fod_basis == BASIS and c.fod_lmax == 8
        for row in rows:
            a, b = int(row["region_a"]) - 1, int(row["region_b"]) - 1
            for measure in ("geodesic_mm", "path_mm", "straight_mm", "connectivity"):
                assert f"{getattr(c, measure)[a, b]:.4f}" == row[measure], (a, b, measure)
        # Each end's own far end: 20 voxels of 2 mm, straight through the crossing.
        for a, b in ((0, 1), (1, 0), (2, 3), (3, 2)):
            assert c.geodesic_mm[a, b] == pytest.approx(40.0, rel=0.005)
            assert c.path_mm[a, b] == pytest.approx(40.0, rel=1e-6)
        assert list(c.to_dataframe()["name_a"][:3]) == ["a0", "a0", "a0"]


def test_bad_calls_are_refused(crossing):
    _, path, _ = crossing
    with pytest.raises(ValueError, match="method='dijkstra'"):
        stvd.fod_paths(path, SEED, TARGETS, fod_basis=BASIS, method="stvd")
    with pytest.raises(ValueError, match="fod_basis"):
        stvd.fod_paths(path, SEED, TARGETS)
    with pytest.raises(ValueError, match="target"):
        stvd.fod_paths(path, SEED, fod_basis=BASIS)
    with pytest.raises(ValueError, match="outside the image"):
        stvd.fod_paths(path, SEED, (30, 10, 1), fod_basis=BASIS)
    with pytest.raises(TypeError):
        stvd.fod_paths(path, SEED, TARGETS, fod_basis=BASIS, step=0.5)  # no tracing: no such keyword
    with pytest.raises(ValueError, match="method='dijkstra'"):
        stvd.fod_connectivity(path, np.ones((21, 21, 3)), fod_basis=BASIS, method="lanthier")


def test_report_pages_of_fod_runs_state_the_metric_and_draw_the_run(tmp_path, crossing):
    """`--report` of FOD runs (docs/report.md): the page states the metric
    (FOD, basis, frame, lmax, floor, power), draws the map, the paths or
    the regions as for tensors, and links and embeds nothing from outside
    (data: URIs only; docs/reliability.md, "Security")."""
    _, path, _ = crossing
    labels = np.zeros((21, 21, 3), np.int16)
    labels[0, 10, 1], labels[20, 10, 1], labels[10, 0, 1], labels[10, 20, 1] = 1, 2, 3, 4
    nib.save(nib.Nifti1Image(labels, AFFINE), tmp_path / "ends.nii.gz")
    fod = ["--fod-basis", BASIS, "--fod-floor", "0.2", "--fod-power", "2"]
    tool("distance", path, *fod, "--seed-voxel", "0,10,1", "-o", tmp_path / "d.nii.gz", "--report",
         tmp_path / "distance.html")
    tool("path", path, *fod, "--seed-voxel", "0,10,1", "--target-voxel", "20,10,1", "-o", tmp_path / "p.tck",
         "--report", tmp_path / "path.html")
    tool("connectivity", path, *fod, "--labels", tmp_path / "ends.nii.gz", "-o", tmp_path / "c.tsv", "--report",
         tmp_path / "connectivity.html")
    note = (f"FOD image read in the basis {BASIS}, in the voxel frame (the default for this basis and format), lmax 8; "
            "metric: the convexified FOD norm F* (floor 0.2, power 2, 668 sampling directions)")
    for name in ("distance", "path", "connectivity"):
        text = (tmp_path / f"{name}.html").read_text()
        assert note in text, name
        # The statistics table lists the parameters too.
        assert f"<tr><th>parameters.fod_basis</th><td class=\"mono\">{BASIS}</td></tr>" in text, name
        assert "<tr><th>parameters.metric</th><td class=\"mono\">fod</td></tr>" in text, name
        for link in re.findall(r"(?:src|href)=\"([^\"]*)\"", text):
            assert link.startswith(("data:", "#")), (name, link[:40])
        assert "http://" not in text and "https://" not in text, name
    distance_page = (tmp_path / "distance.html").read_text()
    assert "Slices through voxel (0, 10, 1): distance map over GFA" in distance_page
    assert "GFA: the generalised fractional anisotropy of the FOD, from its coefficients" in distance_page
    path_page = (tmp_path / "path.html").read_text()
    assert "<table id=\"stvd-paths\">" in path_page and "voxel (20, 10, 1)" in path_page
    assert "geodesic distance heat map" in (tmp_path / "connectivity.html").read_text()


def page_parts(text):
    """The parts of a run page that say what the run was and drew, which a
    page made from Python objects must share with the tool's page of the
    same run (the command line, times and pictures differ)."""
    parts = {"title": re.search(r"<title>(.*?)</title>", text).group(1),
             "notes": re.search(r"<div class=\"notes\" id=\"stvd-notes\">.*?</div>", text).group(0),
             "slices": re.search(r"<h2>Slices through.*?</h2>", text).group(0),
             "background": re.search(r"\bG?FA: [^<]*", text).group(0),
             "paths": (re.search(r"<table id=\"stvd-paths\">.*?</table>", text) or re.match("", "")).group(0),
             "heat maps": re.findall(r"alt=\"([^\"]*heat map)\"", text),
             "warnings": (re.search(r"<div class=\"warnings\".*?</div>", text) or re.match("", "")).group(0)}
    for key in ("metric", "method", "stencil", "fod_basis", "fod_basis_given", "fod_frame", "fod_frame_stated",
                "fod_lmax", "fod_floor", "fod_power", "fod_directions", "fod_norm", "mask"):
        row = re.search(rf"<tr><th>parameters\.{key}</th><td class=\"mono\">([^<]*)</td></tr>", text)
        parts[f"parameters.{key}"] = row.group(1) if row else None
    for key in ("seed_count", "voxels.domain", "propagation.finalized_vertices", "distance_mm.max",
                "regions.count"):
        row = re.search(rf"<tr><th>{re.escape(key)}</th><td class=\"mono\">([^<]*)</td></tr>", text)
        parts[key] = row.group(1) if row else None
    return parts


def test_pages_from_python_objects_are_the_tools_pages_of_the_same_runs(tmp_path, crossing):
    """stvd.report.write_report takes the objects of stvd.fod_distance,
    stvd.fod_paths and stvd.fod_connectivity and writes the page the tool's
    --report writes for the same run: the same title, metric's note
    (basis as resolved and as given, frame, lmax, floor, power, sampling
    directions, the norm and the method), slices, background, path table,
    heat maps and parameters; and, like every page, only data: images."""
    import stvd.report

    _, path, _ = crossing
    labels = np.zeros((21, 21, 3), np.int16)
    labels[0, 10, 1], labels[20, 10, 1], labels[10, 0, 1], labels[10, 20, 1] = 1, 2, 3, 4
    nib.save(nib.Nifti1Image(labels, AFFINE), tmp_path / "ends.nii.gz")
    # The frame stated, the cost's floor and power not the defaults.
    given = dict(fod_basis=BASIS, fod_floor=0.2, fod_power=2.0, fod_frame="voxel")
    flags = ["--fod-basis", BASIS, "--fod-floor", "0.2", "--fod-power", "2", "--fod-frame", "voxel"]
    seed, target = "0,10,1", "20,10,1"
    tool("distance", path, *flags, "--seed-voxel", seed, "-o", tmp_path / "d.nii.gz", "--report",
         tmp_path / "tool_distance.html")
    tool("path", path, *flags, "--seed-voxel", seed, "--target-voxel", target, "-o", tmp_path / "p.tck",
         "--report", tmp_path / "tool_path.html")
    tool("connectivity", path, *flags, "--labels", tmp_path / "ends.nii.gz", "-o", tmp_path / "c.tsv", "--report",
         tmp_path / "tool_connectivity.html")

    distance = stvd.fod_distance(path, SEED, **given)
    paths = stvd.fod_paths(path, SEED, [(20, 10, 1)], **given)
    connectivity = stvd.fod_connectivity(path, tmp_path / "ends.nii.gz", **given)
    summaries = {"distance": stvd.report.write_report(tmp_path / "python_distance.html", distance),
                 "path": stvd.report.write_report(tmp_path / "python_path.html", paths=paths),
                 "connectivity": stvd.report.write_report(tmp_path / "python_connectivity.html",
                                                          connectivity=connectivity, labels=tmp_path / "ends.nii.gz")}
    for kind in ("distance", "path", "connectivity"):
        tool_page = (tmp_path / f"tool_{kind}.html").read_text()
        python_page = (tmp_path / f"python_{kind}.html").read_text()
        mine, theirs = page_parts(python_page), page_parts(tool_page)
        assert mine == theirs, (kind, {k: (mine[k], theirs[k]) for k in mine if mine[k] != theirs[k]})
        assert summaries[kind]["kind"] == kind and summaries[kind]["subject"] == "crossing_fod"
        assert "FOD image read in the basis descoteaux07_legacy, in the voxel frame (stated), lmax 8" in mine["notes"]
        for link in re.findall(r"(?:src|href)=\"([^\"]*)\"", python_page):
            assert link.startswith(("data:", "#")), (kind, link[:40])
        assert "http://" not in python_page and "https://" not in python_page, kind
    notes = page_parts((tmp_path / "python_distance.html").read_text())["notes"]
    assert ("metric: the convexified FOD norm F* (floor 0.2, power 2, 668 sampling directions) along the lattice "
            "directions of order 2 (49 per voxel), interpolated, STVD (docs/fod.md)") in notes
    notes = page_parts((tmp_path / "python_path.html").read_text())["notes"]
    assert "along the 26 neighbour directions, Dijkstra (docs/fod.md)" in notes
    assert "<td>voxel (20, 10, 1)</td>" in page_parts((tmp_path / "python_path.html").read_text())["paths"]


def test_a_page_from_python_takes_the_basis_as_given_and_refuses_mixed_runs(tmp_path, crossing):
    """An alias given ("mrtrix3" is tournier07 in the scanner frame) is shown
    as given beside the basis resolved; a tensor keyword or a tensor run's
    object with an FOD run's is refused, as is an image that no FOD run
    made."""
    import stvd.report

    fit, _, _ = crossing
    distance = stvd.fod_distance(fit.shm_coeff, SEED, fod_basis="mrtrix3", affine=AFFINE)
    stvd.report.write_report(tmp_path / "alias.html", distance)
    text = (tmp_path / "alias.html").read_text()
    assert ("FOD image read in the basis tournier07 (given as mrtrix3), in the scanner frame (the default for this "
            "basis and format), lmax 8") in text
    assert "<title>stvd distance: run</title>" in text  # an array has no file name
    with pytest.raises(ValueError, match="tensor keywords do not apply"):
        stvd.report.write_report(tmp_path / "x.html", distance, tensor_order="fsl")
    tensor_run = stvd.propagate(np.tile(np.eye(3), (21, 21, 3, 1, 1)), (0, 10, 1), affine=AFFINE)
    with pytest.raises(TypeError, match="a tensor run's does not go on an FOD run's page"):
        stvd.report.write_report(tmp_path / "x.html", tensor_run, paths=stvd.fod_paths(
            fit.shm_coeff, SEED, [(20, 10, 1)], fod_basis="mrtrix3", affine=AFFINE))
    with pytest.raises(TypeError, match="holds no FOD run"):
        stvd.report.write_report(tmp_path / "x.html", nib.Nifti1Image(np.zeros((21, 21, 3), np.float32), AFFINE))
    assert not (tmp_path / "x.html").exists()


def test_fod_pages_draw_the_fods_gfa_under_the_run(tmp_path, crossing):
    """An FOD run's page draws the FOD's generalised fractional anisotropy
    (GFA) where a tensor run's draws FA, labelled as GFA, from the tool and
    from Python alike: the GFA of the coefficients (stvd._core.fod_gfa, held
    to DIPY's in test_fod_distance.py), 0 outside the run's mask."""
    import stvd.report

    _, path, in_bundle = crossing
    inside = np.zeros((21, 21, 3), bool)
    for i in range(21):
        for j in range(21):
            inside[i, j, :] = in_bundle(0, i, j) or in_bundle(1, i, j)
    mask = inside.astype(np.uint8)
    nib.save(nib.Nifti1Image(mask, AFFINE), tmp_path / "mask.nii.gz")
    tool("distance", path, "--fod-basis", BASIS, "--seed-voxel", "0,10,1", "--mask", tmp_path / "mask.nii.gz", "-o",
         tmp_path / "d.nii.gz", "--report", tmp_path / "tool.html")
    distance = stvd.fod_distance(path, SEED, fod_basis=BASIS, mask=tmp_path / "mask.nii.gz")
    gfa, affine = stvd._core.fod_gfa(str(path), BASIS)
    assert np.allclose(affine, AFFINE) and gfa.shape == (21, 21, 3)
    assert np.array_equal(distance.extra["stvd_fod_run"].gfa, gfa)
    assert 0.3 < gfa[inside].min() and gfa.max() <= 1.0
    stvd.report.write_report(tmp_path / "python.html", distance)
    for name in ("tool", "python"):
        text = (tmp_path / f"{name}.html").read_text()
        assert "Slices through voxel (0, 10, 1): distance map over GFA</h2>" in text, name
        assert ("GFA: the generalised fractional anisotropy of the FOD, from its coefficients (0 outside the "
                "domain).") in text, name
        assert "not reached: GFA only." in text, name
