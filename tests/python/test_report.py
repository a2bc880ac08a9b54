"""The QC report (stvd.report, `stvd report`, `--report`): what a page shows,
where its letters come from, and what it never does (fetch anything,
overwrite an input, leave half a file)."""

import base64
import io
import os
import re
import subprocess
import sys

import nibabel as nib
import numpy as np
import pytest

import stvd
import stvd.report
from conftest import CC_BODY, CST_L, DIPY_5D, FSL_6, MASK, SAMPLE, TOOL, run_tool

FIGURE = re.compile(r"<figure class=\"slice\" data-plane=\"(\w+)\" data-left=\"(\w)\" data-right=\"(\w)\" "
                    r"data-top=\"(\w)\" data-bottom=\"(\w)\">.*?<img src=\"data:image/png;base64,([^\"]+)\"")


def slices(page_text):
    """plane -> (letters left, right, top, bottom; the picture as an RGB array)."""
    import matplotlib.image

    found = {}
    for plane, left, right, top, bottom, data in FIGURE.findall(page_text):
        picture = matplotlib.image.imread(io.BytesIO(base64.b64decode(data)), format="png")
        found[plane] = ((left, right, top, bottom), picture[:, :, :3])
    return found


def seed_marker_x(picture):
    """Where the magenta seed marker is across the picture, 0 (left) to 1 (right)."""
    r, g, b = picture[:, :, 0], picture[:, :, 1], picture[:, :, 2]
    columns = np.nonzero((r > 0.85) & (g < 0.25) & (b > 0.85))[1]
    assert columns.size > 20, "no seed marker in the picture"
    return columns.mean() / picture.shape[1]


@pytest.fixture(scope="module")
def flipped_brain(tmp_path_factory):
    """The shipped brain with its header flipped left-right: the same voxels,
    the first world axis negated, so that what was the patient's left is now
    the patient's right."""
    image = nib.load(DIPY_5D)
    flip = np.diag([-1.0, 1.0, 1.0, 1.0])
    header = image.header.copy()
    flipped = nib.Nifti1Image(np.asanyarray(image.dataobj), flip @ image.affine, header)
    flipped.set_sform(flip @ image.affine, code=1)
    flipped.set_qform(flip @ image.affine, code=1)
    path = tmp_path_factory.mktemp("flipped") / "flipped.nii.gz"
    nib.save(flipped, path)
    return path


def distance_report(tmp_path, tensors, seed, *options):
    page = tmp_path / "report.html"
    run_tool("distance", tensors, "--seed-voxel", ",".join(map(str, seed)), "-o", tmp_path / "d.nii.gz", "-q",
             "--report", page, *options)
    return page.read_text()


@pytest.mark.parametrize("convention", ["neurological", "radiological"])
def test_letters_and_picture_follow_the_header(tmp_path, flipped_brain, convention):
    # CST_L lies in the left hemisphere of the shipped brain (RAS x = -19 mm):
    # the seed marker must be on the side of the axial and coronal slices that
    # is lettered L. Flipped in the header, the same voxel lies in the right
    # hemisphere, and the marker must be on the side lettered R. A report
    # that ignored the direction cosines (letters or picture) fails one case.
    for tensors, side in ((DIPY_5D, "L"), (flipped_brain, "R")):
        folder = tmp_path / side
        folder.mkdir()
        stvd.report.write_run_report(folder / "report.html", _stats_of_run(folder, tensors, CST_L),
                                     convention=convention)
        page_text = (folder / "report.html").read_text()
        assert f"data-convention=\"{convention}\"" in page_text
        shown = slices(page_text)
        for plane in ("axial", "coronal"):
            (left, right, top, bottom), picture = shown[plane]
            assert {left, right} == {"L", "R"}
            marker_side = left if seed_marker_x(picture) < 0.5 else right
            assert marker_side == side, (plane, convention, tensors)
            # Neurological: the patient's left on the left of the screen.
            assert left == ("L" if convention == "neurological" else "R")
        assert shown["axial"][0][2:] == ("A", "P")
        assert shown["coronal"][0][2:] == ("S", "I")
        assert shown["sagittal"][0] == ("A", "P", "S", "I")


def _stats_of_run(folder, tensors, seed):
    stats = folder / "run.json"
    run_tool("distance", tensors, "--seed-voxel", ",".join(map(str, seed)), "-o", folder / "d.nii.gz", "-q",
             "--stats", stats)
    return stats


def test_the_tools_page_shows_the_run(tmp_path):
    text = distance_report(tmp_path, DIPY_5D, CC_BODY, "--mask", MASK)
    # Version and command line, the statistics table, the warnings.
    assert f"stvd {stvd.__version__}" in text
    assert re.search(r"id=\"stvd-command-line\">stvd distance \S+dti_tensor_dipy5d.nii.gz --seed-voxel 55,54,15", text)
    assert "<table id=\"stvd-statistics\">" in text and "parameters.tensor_frame" in text
    assert "873 of 132,892 domain voxels (0.66 %) had their tensors repaired" in text
    assert "in the voxel frame (the default for this layout: check it)" in text
    assert "orientation LAS, oblique by 5.7 degrees" in text
    assert len(slices(text)) == 3
    summary = stvd.report.cohort_entries_from_folder(tmp_path)[0]
    # Routine repairs (0.66 % of the domain) are information, not a warning.
    assert summary["status"] == "ok" and summary["figures"]["max_distance_mm"] == pytest.approx(91.6, abs=0.05)


def test_a_page_fetches_nothing(tmp_path):
    text = distance_report(tmp_path, DIPY_5D, CC_BODY)
    sources = re.findall(r"(?:src|href)=\"([^\"]*)\"", text)
    assert sources and all(s.startswith("data:image/png;base64,") for s in sources)
    assert "<link" not in text and "@import" not in text and "url(" not in text


def test_warnings_name_what_a_reviewer_must_see(tmp_path):
    # Label seeds partly outside the domain, and a distance limit that
    # leaves most of the brain unreached.
    image = nib.load(DIPY_5D)
    labels = np.zeros(image.shape[:3], np.uint8)
    labels[53:58, 52:57, 14:17] = 1
    labels[0:2, 0:2, 0:2] = 1  # a corner of the image: no tensor there
    nib.save(nib.Nifti1Image(labels, image.affine), tmp_path / "seeds.nii.gz")
    page = tmp_path / "r.html"
    run_tool("distance", DIPY_5D, "--seeds", tmp_path / "seeds.nii.gz", "--max-distance", "20", "-o",
             tmp_path / "d.nrrd", "-q", "--report", page)
    text = page.read_text()
    assert "8 seed label voxels lie outside the domain and were left out." in text
    assert re.search(r"[\d,]+ of 132,892 domain voxels \([\d.]+ %\) were not reached \(the propagation stopped at "
                     r"--max-distance\)", text)


def test_path_and_connectivity_pages(tmp_path):
    image = nib.load(DIPY_5D)
    regions = np.zeros(image.shape[:3], np.int16)
    for label, (i, j, k) in ((3, CC_BODY), (5, CST_L), (8, (41, 51, 12))):
        regions[i - 1:i + 2, j - 1:j + 2, k - 1:k + 2] = label
    nib.save(nib.Nifti1Image(regions, image.affine), tmp_path / "regions.nii.gz")
    run_tool("path", DIPY_5D, "--seed-voxel", "55,54,15", "--target-voxel", "68,50,11", "--target-voxel", "41,51,12",
             "-o", tmp_path / "p.vtk", "-q", "--report", tmp_path / "path.html")
    text = (tmp_path / "path.html").read_text()
    assert "<table id=\"stvd-paths\">" in text and text.count("voxel (68, 50, 11)") == 1
    assert "Slices through voxel (55, 54, 15): distance map over FA" in text
    run_tool("connectivity", DIPY_5D, "--labels", tmp_path / "regions.nii.gz", "-o", tmp_path / "c.tsv", "-q",
             "--report", tmp_path / "connectivity.html")
    text = (tmp_path / "connectivity.html").read_text()
    assert "geodesic distance heat map" in text and "Regions: the labelled regions" in text


def test_python_objects_give_the_page_of_the_tool(tmp_path):
    result = stvd.propagate(DIPY_5D, CC_BODY)
    paths = stvd.trace_paths(result, [CST_L])
    summary = stvd.report.write_report(tmp_path / "python.html", result, paths=paths, command_line="test")
    assert summary["kind"] == "path" and summary["figures"]["paths"] == 1
    text = (tmp_path / "python.html").read_text()
    assert "873 of 132,892 domain voxels (0.66 %) had their tensors repaired" in text
    tool = tmp_path / "tool"
    tool.mkdir()
    distance_report(tool, DIPY_5D, CC_BODY)
    tool_summary = stvd.report.cohort_entries_from_folder(tool)[0]
    for key in ("domain_voxels", "repaired_voxels", "reached_percent", "max_distance_mm", "median_distance_mm"):
        assert summary["figures"][key] == tool_summary["figures"][key], key


def _note(text):
    """The page's note on how the tensors were read."""
    found = re.search(r"Tensors read as [^<]*", text)
    assert found, "no note on the tensors"
    return found.group(0)


def test_a_page_states_what_the_run_had_from_python_and_from_the_tool(tmp_path):
    # From Python, a DIPY (3, 3) array was described as "NIfTI six-volume,
    # component order fsl", its input as `tensors`, and every cap as "n/a".
    image = nib.load(DIPY_5D)
    lower = np.asanyarray(image.dataobj)[:, :, :, 0, :]
    xx, xy, yy, xz, yz, zz = (lower[..., q] for q in range(6))
    matrices = np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1), np.stack([xz, yz, zz], -1)], -2)
    result = stvd.propagate(matrices, CC_BODY, affine=image.affine, max_anisotropy=50, mask=MASK)
    stvd.report.write_report(tmp_path / "matrices.html", result, command_line="test")
    text = (tmp_path / "matrices.html").read_text()
    assert _note(text) == ("Tensors read as (X, Y, Z, 3, 3) array of symmetric matrices, component order none (3x3 "
                           "matrices), in the voxel frame (the default for this layout: check it); metric G = (D/MD)^-1; "
                           "eigenvalue-ratio cap 50.")
    assert "Input <code>array of shape (112, 112, 32, 3, 3), float32</code>" in text
    assert "beyond the eigenvalue-ratio cap of 50)" in text
    # The words of the page, not the bytes of its embedded slice images,
    # whose base64 text may hold "n/a" by chance (it did, once the
    # distances changed in their last digits).
    words = re.sub(r"data:[^\"']*", "", text)
    assert "n/a" not in words and "six-volume" not in words
    assert "stvd distance: run" in text  # not named after `tensors`

    # Six components in a stated order, metric tensors (no cap).
    result = stvd.propagate(lower, CC_BODY, affine=image.affine, tensor_order="lower", tensor_frame="voxel",
                            accept_implausible_tensors=True, tensor_kind="metric")
    stvd.report.write_report(tmp_path / "six.html", result, command_line="test")
    note = _note((tmp_path / "six.html").read_text())
    assert note.startswith("Tensors read as (X, Y, Z, 6) array, component order lower (stated), in the voxel frame "
                           "(stated)")
    assert note.endswith("eigenvalue-ratio cap none (tensors taken as given).")

    # A NiBabel image: its layout, the order its intent fixes, its file.
    result = stvd.propagate(image, CC_BODY, max_anisotropy=30)
    stvd.report.write_report(tmp_path / "image.html", result, command_line="test")
    text = (tmp_path / "image.html").read_text()
    assert _note(text).startswith("Tensors read as NIfTI 5D SYMMATRIX, component order lower (from the layout)")
    assert _note(text).endswith("eigenvalue-ratio cap 30.")
    assert f"Input <code>NiBabel image of {DIPY_5D}</code>" in text

    # A connectivity page: the run's own reading (a six-volume file needs its
    # order; the page re-read it without and failed), not a new one.
    regions = np.zeros(image.shape[:3], np.int16)
    for label, (i, j, k) in ((3, CC_BODY), (5, CST_L)):
        regions[i - 1:i + 2, j - 1:j + 2, k - 1:k + 2] = label
    table = stvd.connectivity(FSL_6, regions, tensor_order="fsl", max_anisotropy=40, threads=1)
    stvd.report.write_report(tmp_path / "connectivity.html", connectivity=table, tensors=FSL_6, command_line="test")
    text = (tmp_path / "connectivity.html").read_text()
    assert _note(text).startswith("Tensors read as NIfTI six-volume, component order fsl (stated), in the voxel frame")
    assert _note(text).endswith("eigenvalue-ratio cap 40.")
    assert f"Input <code>{FSL_6}</code>" in text

    # The tool's page: the cap it ran with.
    text = distance_report(tmp_path, DIPY_5D, CC_BODY, "--max-anisotropy", "20")
    assert _note(text).endswith("eigenvalue-ratio cap 20.")
    assert "beyond the eigenvalue-ratio cap of 20)" in text


def _captions(text):
    return re.findall(r"<figcaption>([^<]*)</figcaption>", text)


def _colour_pixels(picture, colour):
    """Where a picture has exactly this colour (to a tenth)."""
    rgb = np.array([int(colour[n:n + 2], 16) / 255.0 for n in (1, 3, 5)])
    return np.abs(picture - rgb).max(axis=2) < 0.1


def test_the_slices_show_what_lies_under_the_marks_and_the_badge_means_something(tmp_path):
    seed_colour, target_colour = "#ff00ff", "#00ffff"  # stvd._report_slices' SEED_COLOUR, TARGET_COLOUR

    # The captions number the slices as the heading's voxel does: this LAS
    # brain's sagittal slice through i = 55 was captioned "slice 56".
    text = distance_report(tmp_path, DIPY_5D, CC_BODY)
    assert "Slices through voxel (55, 54, 15)" in text
    assert _captions(text) == ["axial slice k = 15", "coronal slice j = 54", "sagittal slice i = 55"]

    # A seed voxel is a ring: its centre shows what lies there (the path
    # start), not a solid magenta disc over it.
    image = nib.load(DIPY_5D)
    targets = np.zeros(image.shape[:3], np.uint8)
    targets[60:64, 52:56, 15] = 1  # a target region in the seed's axial slice
    nib.save(nib.Nifti1Image(targets, image.affine), tmp_path / "targets.nii.gz")
    page = tmp_path / "path.html"
    run_tool("path", DIPY_5D, "--seed-voxel", ",".join(map(str, CC_BODY)), "--targets", tmp_path / "targets.nii.gz",
             "-o", tmp_path / "p.trk", "-q", "--report", page)
    text = page.read_text()
    (_, picture) = slices(text)["axial"]
    seed = _colour_pixels(picture, seed_colour)
    rows, columns = np.nonzero(seed)
    centre = (int(round(rows.mean())), int(round(columns.mean())))
    assert not seed[centre[0] - 2:centre[0] + 3, centre[1] - 2:centre[1] + 3].any(), "the seed's centre is covered"
    path_colour = _colour_pixels(picture, "#1f77b4")  # the first path (tab10)
    near = path_colour[centre[0] - 6:centre[0] + 7, centre[1] - 6:centre[1] + 7]
    assert near.any(), "the path start is hidden"
    # The target region is marked (an outline in its own colour), and said so.
    assert _colour_pixels(picture, target_colour).sum() > 20
    assert "Targets:" in text

    # The distance map lets FA show through: the same page over the real FA
    # and over FA 0 differs, in the reached brain, by at least 60 % of FA.
    result = stvd.propagate(DIPY_5D, CC_BODY)
    fa = nib.load(SAMPLE / "dti_FA.nii.gz").get_fdata()
    over_fa, over_zero = tmp_path / "fa.html", tmp_path / "zero.html"
    stvd.report.write_report(over_fa, result, fa=fa, command_line="test")
    stvd.report.write_report(over_zero, result, fa=np.zeros_like(fa), command_line="test")
    a, b = slices(over_fa.read_text())["axial"][1], slices(over_zero.read_text())["axial"][1]
    shown = np.abs(a - b).mean(axis=2)
    brain = shown > 0.02
    grey = np.asarray(stvd._report_slices.DisplayGrid(result.affine, result.shape).turn(np.clip(fa, 0, 1)))[:, :, 15]
    assert brain.mean() > 0.2
    assert shown[brain].mean() >= 0.6 * grey[grey > 0.02].mean(), "the overlay hides FA"

    # A badge that means something: routine repairs (0.66 % of the domain)
    # are a note; repairs of more than 1 % are a warning.
    assert "warnings" not in re.search(r"<h1>.*?</h1>", distance_report(tmp_path, DIPY_5D, CC_BODY)).group(0)
    capped = distance_report(tmp_path, DIPY_5D, CC_BODY, "--max-anisotropy", "5")
    heading = re.search(r"<h1>.*?</h1>", capped).group(0)
    assert "status-warnings" in heading
    assert re.search(r"domain voxels \([\d.]+ %\) had their tensors repaired .*: more than the 1 % a good fit has",
                     capped)
    # "1 warning", not "1 warnings".
    stvd.report.write_cohort_index(tmp_path / "index.html", [{"subject": "s", "status": "warnings", "warnings": 1}])
    index = (tmp_path / "index.html").read_text()
    assert "<td>1 warning</td>" in index and "1 subject: 1 with a warning." in index
    assert "1 warnings" not in index


def test_cohort_index_from_entries_and_from_a_folder(tmp_path):
    for subject in ("sub-01", "sub-02"):
        folder = tmp_path / subject
        folder.mkdir()
        distance_report(folder, DIPY_5D, CC_BODY)
    (tmp_path / "sub-03").mkdir()  # a subject whose run left no page
    counts = stvd.report.cohort_index_from_folder(tmp_path)
    assert counts == {"ok": 2, "missing": 1}
    text = (tmp_path / "index.html").read_text()
    assert text.count("<a href=\"./sub-01/report.html\">") == 2  # the name and the thumbnail
    assert "3 subjects: 1 missing, 2 ok." in text
    # The cohort run's form: entries with a failed subject and its error.
    entries = stvd.report.cohort_entries_from_folder(tmp_path)[:2]
    entries.append({"subject": "sub-04", "status": "failed", "error": "t.nii.gz: cannot read"})
    stvd.report.write_cohort_index(tmp_path / "cohort.html", entries)
    assert "t.nii.gz: cannot read" in (tmp_path / "cohort.html").read_text()


def test_an_output_is_never_an_input(tmp_path):
    page = tmp_path / "report.html"
    distance_report(tmp_path, DIPY_5D, CC_BODY)
    before = page.read_bytes()
    os.symlink(page, tmp_path / "link.html")
    with pytest.raises(stvd.report.ReportError, match=r"link.html: the QC report is the report of sub "):
        stvd.report.write_cohort_index(tmp_path / "link.html", [{"subject": "sub", "status": "ok", "report": page}])
    assert page.read_bytes() == before
    message = run_tool("report", "--stats", tmp_path / "d.nii.gz", "-o", tmp_path / "d.nii.gz", check=False)
    assert message.returncode == 2 and message.stderr.strip().endswith("d.nii.gz: a report is an .html file")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.nii.gz", "link.html", "report.html"]


def interpreter_with(folder, files):
    """The environment of a tool run whose report uses an interpreter
    (STVD_PYTHON) with ``files`` (name: text) in its own site packages: a
    virtual environment that sees the system's packages too. (PYTHONPATH
    would not do: the tool runs Python isolated from it.)"""
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(folder)], check=True)
    site = next(folder.glob("lib/python3*/site-packages"))
    for name, text in files.items():
        (site / name).parent.mkdir(parents=True, exist_ok=True)
        (site / name).write_text(text)
    return dict(os.environ, STVD_PYTHON=str(folder / "bin" / "python3"))


def test_what_python_says_while_importing_does_not_stop_the_report(tmp_path):
    # matplotlib's first run on a machine says on stderr that it builds its
    # font cache; the tool waits for the child's "ready" past such lines.
    environment = interpreter_with(tmp_path / "python", {"sitecustomize.py": (
        "import sys\nprint('Matplotlib is building the font cache; this may take a moment.', file=sys.stderr)\n")})
    process = subprocess.run([str(TOOL), "distance", str(DIPY_5D), "--seed-voxel", "55,54,15", "-o",
                              str(tmp_path / "d.nii.gz"), "-q", "--report", str(tmp_path / "r.html")],
                             capture_output=True, text=True, env=environment)
    assert process.returncode == 0, process.stderr
    assert "stvd-report-summary" in (tmp_path / "r.html").read_text()


def test_without_matplotlib_nothing_is_written(tmp_path):
    # The interpreter's matplotlib cannot be imported.
    environment = interpreter_with(tmp_path / "python", {
        "matplotlib/__init__.py": "raise ImportError('no matplotlib here')\n"})
    process = subprocess.run([str(TOOL), "distance", str(DIPY_5D), "--seed-voxel", "55,54,15", "-o",
                              str(tmp_path / "d.nii.gz"), "--report", str(tmp_path / "r.html")],
                             capture_output=True, text=True, env=environment)
    assert process.returncode == 1
    assert process.stderr.startswith("stvd: report: the report needs matplotlib (Debian: python3-matplotlib) for ")
    assert process.stderr.count("\n") == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["python"]


def test_subject_names_the_page_and_is_shown_as_text(tmp_path):
    """`--subject NAME` (and write_report's subject=) names the page in its
    title, heading and run summary instead of the input's file name; any
    text, shown as text: <, & and quotes never become markup. Without
    --report it is refused in one line, with nothing written."""
    import html

    name = "sub-01 <b>\"ses\" & 'run'</b>"
    page = tmp_path / "named.html"
    run_tool("distance", DIPY_5D, "--seed-voxel", "55,54,15", "-o", tmp_path / "d.nii.gz", "-q", "--report", page,
             "--subject", name)
    text = page.read_text()
    title = html.escape(f"stvd distance: {name}", quote=True)
    assert f"<title>{title}</title>" in text and f"<h1>{title} " in text
    assert "<b>" not in text and "dti_tensor_dipy5d</title>" not in text
    # The cohort index reads the name back from the page's summary.
    entry = stvd.report.cohort_entries_from_folder(tmp_path)[0]
    assert entry["subject"] == name
    stvd.report.write_cohort_index(tmp_path / "index.html", [dict(entry, report=str(page))])
    index = (tmp_path / "index.html").read_text()
    assert html.escape(name, quote=True) in index and "<b>" not in index
    # A name that looks like an option is a name.
    run_tool("distance", DIPY_5D, "--seed-voxel", "55,54,15", "-o", tmp_path / "d.nii.gz", "-q", "--report",
             tmp_path / "dash.html", "--subject=-q")
    assert "<title>stvd distance: -q</title>" in (tmp_path / "dash.html").read_text()
    # From Python, the same title.
    result = stvd.propagate(DIPY_5D, CC_BODY)
    stvd.report.write_report(tmp_path / "python.html", result, subject=name)
    assert f"<title>{title}</title>" in (tmp_path / "python.html").read_text()
    # Without a page to name: refused, nothing written.
    refused = run_tool("distance", DIPY_5D, "--seed-voxel", "55,54,15", "-o", tmp_path / "none.nii.gz",
                       "--subject", "x", check=False)
    assert refused.returncode == 2 and refused.stderr == ("stvd: --subject names the QC page: add --report "
                                                          "FILE.html\n")
    assert not (tmp_path / "none.nii.gz").exists()
