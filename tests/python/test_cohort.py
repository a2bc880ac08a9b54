"""`stvd cohort` and stvd.cohort.run on a small synthetic cohort made from the
shipped brain (synthetic_cohort.py, cropped): the manifest's checks, the
outputs against the tool's, the embedded Dask cluster against a serial run
(the same bytes), re-runs, and outputs that would be inputs."""

import html
import json
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys

import nibabel as nib
import numpy as np
import pytest

import stvd.cohort
import stvd.report
from conftest import TOOL, run_tool
from synthetic_cohort import make_cohort

SUBJECTS = 7  # base, flipped, seed_outside, s02..s04, corrupt

# A writer killed (SIGKILL) while it stages argv[1]: it leaves its staging
# folder, with the record of its process, behind.
KILLED_WRITER = """
import os, signal, sys
import stvd
out = stvd.OutputFiles({"output": sys.argv[1]})
def write(staging):
    with open(staging, "wb") as file:
        file.write(b"half")
    os.kill(os.getpid(), signal.SIGKILL)
out.write(sys.argv[1], write)
"""
BAD = {"corrupt", "seed_outside"}


def run_cohort_command(*args):
    """`stvd cohort ...` through the tool, as a user runs it."""
    return subprocess.run([str(TOOL), "cohort", *map(str, args)], capture_output=True, text=True)


def folder_bytes(folder):
    """Every file under ``folder`` by relative path, with its bytes; the
    run.json files (where and how long) and the QC pages and cohort index
    (which say when they were made) are left out."""
    folder = pathlib.Path(folder)
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and p.name not in ("run.json", "report.html", "index.html")}


def qc_pages(folder):
    """The subjects with a QC page in ``folder``, and its status."""
    return {e["subject"]: e["status"] for e in stvd.report.cohort_entries_from_folder(folder)}


@pytest.fixture(scope="module")
def cohort(tmp_path_factory):
    return make_cohort(tmp_path_factory.mktemp("cohort"), subjects=SUBJECTS, crop=True)


@pytest.fixture(scope="module")
def serial(cohort, tmp_path_factory):
    outdir = tmp_path_factory.mktemp("serial") / "out"
    result = stvd.cohort.run(cohort, outdir, serial=True)
    return outdir, result


def test_every_subject_is_computed_and_bad_ones_are_recorded_with_their_error(serial):
    outdir, result = serial
    assert result.workers == 0 and len(result.subjects) == SUBJECTS
    assert set(result.failed) == BAD
    table = (outdir / "cohort.tsv").read_text().splitlines()
    assert table[0].split("\t") == list(stvd.cohort.TABLE_COLUMNS)
    rows = {line.split("\t")[0]: dict(zip(stvd.cohort.TABLE_COLUMNS, line.split("\t"))) for line in table[1:]}
    assert list(rows) == ["base", "flipped", "seed_outside", "s02", "s03", "s04", "corrupt"]  # manifest order
    for subject, row in rows.items():
        files = sorted(p.name for p in (outdir / subject).iterdir())
        if subject in BAD:
            assert row["status"] == "failed" and files == ["error.txt"]
            assert (outdir / subject / "error.txt").read_text() == row["error"] + "\n"
        else:
            assert row["status"] == "ok" and row["error"] == "" and row["regions"] == "4" and row["maps"] == "2"
            assert files == ["connectivity.tsv", "distance_CC_body.nii.gz", "distance_CST_L.nii.gz",
                             "report.html", "run.json", "statistics.json"]
    assert rows["corrupt"]["error"].endswith("corrupt/tensors.nii.gz: the compressed data are damaged or cut short")
    assert "seed voxel" in rows["seed_outside"]["error"] and "outside the domain" in rows["seed_outside"]["error"]


def test_a_subjects_outputs_are_the_tools(serial, cohort, tmp_path):
    outdir, _ = serial
    base = cohort.parent / "base"
    inputs = [base / "tensors.nii.gz", "--mask", base / "mask.nii.gz"]
    run_tool("connectivity", *inputs, "--labels", base / "labels.nii.gz", "-o", tmp_path / "tool.tsv", "-q")
    assert (outdir / "base" / "connectivity.tsv").read_bytes() == (tmp_path / "tool.tsv").read_bytes()
    statistics = json.loads((outdir / "base" / "statistics.json").read_text())
    for seed_set, voxels in statistics["request"]["work"]["seed_sets"].items():
        seeds = [option for voxel in voxels for option in ("--seed-voxel", ",".join(map(str, voxel)))]
        run_tool("distance", *inputs, *seeds, "-o", tmp_path / "tool.nii.gz", "-q")
        tool = nib.load(tmp_path / "tool.nii.gz")
        ours = nib.load(outdir / "base" / f"distance_{seed_set}.nii.gz")
        assert np.array_equal(np.asanyarray(ours.dataobj), np.asanyarray(tool.dataobj))
        assert np.allclose(ours.affine, tool.affine)
        # The statistics record each output's size and digest.
        assert statistics["outputs"][f"distance_{seed_set}.nii.gz"]["bytes"] == os.path.getsize(
            outdir / "base" / f"distance_{seed_set}.nii.gz")


def test_every_good_subject_has_a_qc_page_and_the_index_lists_all_in_the_manifests_order(serial):
    outdir, result = serial
    assert result.index == str(outdir / "index.html")
    entries = {e["subject"]: e for e in stvd.report.cohort_entries_from_folder(outdir)}
    for row in result.subjects:
        subject = row["subject"]
        if subject in BAD:
            assert entries[subject]["status"] == "missing"  # no page; the index says why (below)
        else:
            # The page's summary: this subject's map (the first seed set) and
            # its four regions.
            entry = entries[subject]
            assert entry["report"] == str(outdir / subject / "report.html")
            assert entry["status"] in ("ok", "warnings") and entry["figures"]["regions"] == 4
            assert entry["figures"]["max_distance_mm"] == pytest.approx(
                json.loads((outdir / subject / "statistics.json").read_text())["parts"]["CC_body"]["max_mm"],
                abs=0.01)
            # The page states what the run had (issue 31): the tensors' file,
            # how they were read and the cap, never "n/a".
            page = (outdir / subject / "report.html").read_text()
            note = re.search(r"Tensors read as [^<]*", page).group(0)
            assert re.search(r"component order \w+ \((stated|from the layout)\)", note), note
            assert re.search(r"eigenvalue-ratio cap (\d+|none \(tensors taken as given\))\.$", note), note
            assert re.search(r"<p>Input <code>(NiBabel image of )?/[^<]+</code>", page)
    index = (outdir / "index.html").read_text()
    rows = [index.index(f">{s['subject']}<") for s in result.subjects]
    assert rows == sorted(rows)  # the manifest's order
    for row in result.subjects:
        if row["subject"] in BAD:
            assert html.escape(row["error"]) in index
        else:
            assert f'href="./{row["subject"]}/report.html"' in index


def test_the_same_brain_under_a_flipped_header_gives_the_same_geodesic_distances(serial):
    outdir, _ = serial

    def table(subject):
        lines = (outdir / subject / "connectivity.tsv").read_text().splitlines()[1:]
        return {tuple(line.split("\t")[:2]): float(line.split("\t")[2]) for line in lines}

    base, flipped = table("base"), table("flipped")
    assert base.keys() == flipped.keys()
    # The same to the table's last digits (1e-4 mm). They differed by up to
    # 0.17 % (0.1 % before the any-angle ancestors; the test allowed 1e-3)
    # while a vertex whose key had been raised could be settled by an entry
    # left from its earlier key, which depended on the queue's buckets and
    # the order the voxels were pushed in (relaxation.hpp, settleMin).
    for pair, geodesic in base.items():
        assert flipped[pair] == pytest.approx(geodesic, rel=1e-5), pair


def test_the_embedded_cluster_writes_the_bytes_of_the_serial_run(serial, cohort, tmp_path):
    outdir = tmp_path / "out"
    process = run_cohort_command(cohort, "-o", outdir, "--workers", "2", "--no-progress")
    assert process.returncode == 3, process.stderr  # two subjects failed
    assert "7 subjects: 7 computed on 2 Dask workers" in process.stdout
    assert f"and the index {outdir / 'index.html'}" in process.stdout
    assert folder_bytes(outdir) == folder_bytes(serial[0])
    assert qc_pages(outdir) == qc_pages(serial[0])
    assert not list(outdir.rglob(".stvd-staging-*"))


def test_split_seed_sets_makes_a_task_of_each_part_with_the_same_outputs(serial, cohort, tmp_path):
    result = stvd.cohort.run(cohort, tmp_path / "out", workers=2, split_seed_sets=True)
    assert set(result.failed) == BAD
    assert folder_bytes(tmp_path / "out") == folder_bytes(serial[0])
    assert qc_pages(tmp_path / "out") == qc_pages(serial[0])


def test_a_second_run_computes_only_what_is_missing_or_failed(cohort, tmp_path):
    # A copy of the cohort whose files can be changed.
    data = tmp_path / "data"
    shutil.copytree(cohort.parent, data)
    manifest, outdir = data / "manifest.tsv", tmp_path / "out"
    first = stvd.cohort.run(manifest, outdir, serial=True, report=False)
    assert len(first.computed) == SUBJECTS and first.index is None and not list(outdir.rglob("*.html"))
    stamps = {p: p.stat().st_mtime_ns for p in outdir.rglob("statistics.json")}
    table = (outdir / "cohort.tsv").read_text()

    second = stvd.cohort.run(manifest, outdir, serial=True, report=False)
    assert set(second.computed) == BAD and set(second.failed) == BAD
    assert {p: p.stat().st_mtime_ns for p in outdir.rglob("statistics.json")} == stamps
    assert (outdir / "cohort.tsv").read_text() == table

    # A missing output, a repaired subject: computed again, now complete;
    # what a writer killed while it wrote left there is removed (a staging
    # folder with the record of a process that is gone), and a folder named
    # like one that no run of ours made is not.
    (outdir / "s03" / "distance_CST_L.nii.gz").unlink()
    killed = subprocess.run([sys.executable, "-c", KILLED_WRITER, str(outdir / "s03" / "distance_CST_L.nii.gz")],
                            capture_output=True)
    assert killed.returncode == -signal.SIGKILL, killed.stderr
    [leftover] = [p for p in (outdir / "s03").iterdir() if p.name.startswith(".stvd-staging-")]
    someone = outdir / "s03" / ".stvd-staging-99999999-0"
    someone.mkdir()
    (someone / "notes.txt").write_text("not stvd's")
    shutil.copy(data / "base" / "tensors.nii.gz", data / "corrupt" / "tensors.nii.gz")
    third = stvd.cohort.run(manifest, outdir, serial=True, report=False)
    assert set(third.computed) == {"s03", "corrupt", "seed_outside"} and third.failed == ["seed_outside"]
    assert (outdir / "s03" / "distance_CST_L.nii.gz").is_file() and not leftover.exists()
    assert (someone / "notes.txt").read_text() == "not stvd's"
    assert (outdir / "corrupt" / "connectivity.tsv").read_bytes() == (outdir / "base" / "connectivity.tsv").read_bytes()
    assert not (outdir / "corrupt" / "error.txt").exists()

    # Other options are another request: everything is computed again.
    fourth = stvd.cohort.run(manifest, outdir, serial=True, k=4, report=False)
    assert len(fourth.computed) == SUBJECTS
    assert json.loads((outdir / "base" / "statistics.json").read_text())["request"]["options"]["k"] == 4


def test_seeds_given_as_a_label_image_make_a_map_per_region(serial, cohort, tmp_path):
    # The base subject with its two seed sets drawn as regions 1 and 2 of a
    # label image (region 2 with one more voxel, outside the brain, which is
    # left out), and a subject whose region 3 lies wholly outside.
    base = cohort.parent / "base"
    mask = nib.load(base / "mask.nii.gz")
    statistics = json.loads((serial[0] / "base" / "statistics.json").read_text())
    seed_sets = statistics["request"]["work"]["seed_sets"]
    outside = tuple(int(c) for c in np.argwhere(np.asanyarray(mask.dataobj) == 0)[0])
    labels = np.zeros(mask.shape, np.int16)
    for value, name in ((1, "CC_body"), (2, "CST_L")):
        for voxel in seed_sets[name]:
            labels[tuple(voxel)] = value
    labels[outside] = 2
    nib.save(nib.Nifti1Image(labels, mask.affine), tmp_path / "seeds.nii.gz")
    labels[outside] = 3
    nib.save(nib.Nifti1Image(labels, mask.affine), tmp_path / "seeds_outside.nii.gz")
    files = "\t".join(str(base / f) for f in ("tensors.nii.gz", "labels.nii.gz", "mask.nii.gz"))
    manifest = tmp_path / "manifest.tsv"
    manifest.write_text(f"subject\ttensors\tlabels\tmask\tseeds\nregions\t{files}\tseeds.nii.gz\n"
                        f"region_outside\t{files}\tseeds_outside.nii.gz\n")

    result = stvd.cohort.run(manifest, tmp_path / "out", serial=True, connectivity=False, report=False)
    assert result.failed == ["region_outside"]
    assert sorted(p.name for p in (tmp_path / "out" / "regions").glob("distance_*")) == [
        "distance_label_1.nii.gz", "distance_label_2.nii.gz"]
    for value, name in ((1, "CC_body"), (2, "CST_L")):  # the maps of the seed table's voxels, byte for byte
        assert (tmp_path / "out" / "regions" / f"distance_label_{value}.nii.gz").read_bytes() == (
            serial[0] / "base" / f"distance_{name}.nii.gz").read_bytes()
    parts = json.loads((tmp_path / "out" / "regions" / "statistics.json").read_text())["parts"]
    assert parts["label_1"]["seed_voxels"] == 1 and parts["label_1"]["seed_voxels_left_out"] == 0
    assert parts["label_2"]["seed_voxels"] == 2 and parts["label_2"]["seed_voxels_left_out"] == 1
    error = result.subjects[1]["error"]
    assert "seeds_outside.nii.gz" in error and "(seed region 3)" in error, error


@pytest.mark.parametrize("header, rows, where", [
    ("subject\ttensors\tlabels\tweight", [], "manifest.tsv, row 1, column weight: unknown column"),
    ("subject\ttensors", ["a\tt.nii.gz"], "manifest.tsv, row 1: no column 'labels'"),
    ("subject\ttensors\tlabels", ["a\tt.nii.gz"], "manifest.tsv, row 2: 2 cells, but the header has 3 columns"),
    ("subject\ttensors\tlabels", ["a\tt.nii.gz\tl.nii.gz", "", "a\tu.nii.gz\tl.nii.gz"],
     "manifest.tsv, row 4, column subject: 'a' is also the subject of row 2"),
    ("subject\ttensors\tlabels", ["../a\tt.nii.gz\tl.nii.gz"], "manifest.tsv, row 2, column subject: '../a' cannot"),
    ("subject\ttensors\tlabels", ["a\t\tl.nii.gz"], "manifest.tsv, row 2, column tensors: empty cell"),
    ("subject\ttensors\tlabels\ttensor_order", ["a\tt.nii.gz\tl.nii.gz\tupper"],
     "manifest.tsv, row 2, column tensor_order: 'upper' is not one of lower, fsl, mrtrix"),
    ("subject\ttensors\tlabels", [], "manifest.tsv: no subjects"),
])
def test_a_bad_manifest_is_one_line_naming_file_row_and_column_and_nothing_is_written(tmp_path, header, rows, where):
    manifest = tmp_path / "manifest.tsv"
    manifest.write_text("\n".join([header, *rows]) + "\n")
    process = run_cohort_command(manifest, "-o", tmp_path / "out")
    assert process.returncode == 2
    assert process.stderr.count("\n") == 1 and process.stderr.startswith(f"stvd: {manifest.parent}/{where}")
    assert not (tmp_path / "out").exists()


def test_an_output_that_is_an_input_is_refused_before_anything_is_written(cohort, tmp_path):
    data = tmp_path / "data"
    shutil.copytree(cohort.parent, data)
    manifest = data / "manifest.tsv"
    # The cohort table would be the manifest: OUTDIR is the manifest's
    # folder, reached through a symlink, and the manifest is named cohort.tsv.
    table_named = data / "cohort.tsv"
    manifest.rename(table_named)
    (tmp_path / "link").symlink_to(data)
    before = table_named.read_bytes()
    process = run_cohort_command(table_named, "-o", tmp_path / "link")
    assert process.returncode == 2 and process.stderr.count("\n") == 1
    assert "the output cohort.tsv" in process.stderr and "is the manifest" in process.stderr
    assert table_named.read_bytes() == before
    # A subject's input that is another subject's output (a hard link).
    out = tmp_path / "out"
    (out / "base").mkdir(parents=True)
    os.link(data / "s02" / "tensors.nii.gz", out / "base" / "connectivity.tsv")
    process = run_cohort_command(table_named, "-o", out)
    assert process.returncode == 2
    assert "the output connectivity.tsv of subject base" in process.stderr
    assert "is the tensors input of subject s02" in process.stderr
    assert sorted(p.name for p in out.rglob("*")) == ["base", "connectivity.tsv"]
