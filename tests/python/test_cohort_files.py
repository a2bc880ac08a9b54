"""What a cohort run may remove, read and refuse in a study folder others
share: clean-up removes only what a run of ours recorded writing (never a
subject's input, never a file by the look of its name), staging folders
only when they are demonstrably our leftovers; seeds and run records are
read only as regular files; a seed image on another grid fails its subject
from its header; a manifest that cannot be run is refused before any work,
in one line naming file, row and column (docs/reliability.md, "Security")."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time

import nibabel as nib
import numpy as np
import pytest

import stvd.cohort
from conftest import TOOL
from synthetic_cohort import make_cohort
from test_cohort import KILLED_WRITER


def run_cohort_command(*args, timeout=600):
    return subprocess.run([str(TOOL), "cohort", *map(str, args)], capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def cohort(tmp_path_factory):
    """The synthetic cohort, cropped, of four subjects (base, flipped,
    seed_outside, corrupt)."""
    return make_cohort(tmp_path_factory.mktemp("cohort"), subjects=4, crop=True)


def one_subject(cohort, folder, seeds=None, mask="mask.nii.gz"):
    """A copy of the base subject in ``folder``/base and a manifest of it alone,
    with the mask (and seeds) as given, relative to ``folder``."""
    base = folder / "base"
    base.mkdir(parents=True, exist_ok=True)
    for name in ("tensors.nii.gz", "labels.nii.gz", "mask.nii.gz", "seeds.tsv"):
        shutil.copy(cohort.parent / "base" / name, base / name)
    manifest = folder / "manifest.tsv"
    manifest.write_text("subject\ttensors\tlabels\tmask\tseeds\n"
                        f"base\tbase/tensors.nii.gz\tbase/labels.nii.gz\tbase/{mask}\tbase/{seeds or 'seeds.tsv'}\n")
    return manifest


# --- Clean-up ----------------------------------------------------------------


def test_clean_up_never_removes_an_input_nor_a_file_by_its_name(cohort, tmp_path):
    # The output folder is the study folder: each subject's folder is its
    # data folder, where its mask is named like one of our maps, next to a
    # file of the user's named the same way.
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder, mask="distance_mask.nii.gz")
    shutil.copy(folder / "base" / "mask.nii.gz", folder / "base" / "distance_mask.nii.gz")
    (folder / "base" / "distance_notes.nii.gz").write_bytes(b"the user's")
    before = (folder / "base" / "distance_mask.nii.gz").read_bytes()
    result = stvd.cohort.run(manifest, folder, serial=True, report=False)
    assert result.failed == []
    assert (folder / "base" / "distance_mask.nii.gz").read_bytes() == before
    assert (folder / "base" / "distance_notes.nii.gz").read_bytes() == b"the user's"
    assert (folder / "base" / "distance_CC_body.nii.gz").is_file()


def test_the_maps_of_an_earlier_request_are_removed_as_recorded(cohort, tmp_path):
    # A seed set renamed: the map of the old name, which the earlier run
    # recorded writing, goes; a map of that name that is not the one
    # recorded (its bytes changed since) stays.
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder)
    outdir = tmp_path / "out"
    assert stvd.cohort.run(manifest, outdir, serial=True, report=False).failed == []
    seeds = folder / "base" / "seeds.tsv"
    seeds.write_text(seeds.read_text().replace("CST_L", "CST_left"))
    assert (outdir / "base" / "distance_CST_L.nii.gz").is_file()
    assert stvd.cohort.run(manifest, outdir, serial=True, report=False).failed == []
    assert not (outdir / "base" / "distance_CST_L.nii.gz").exists()
    assert (outdir / "base" / "distance_CST_left.nii.gz").is_file()

    seeds.write_text(seeds.read_text().replace("CST_left", "CST_L"))
    assert stvd.cohort.run(manifest, outdir, serial=True, report=False).failed == []
    with open(outdir / "base" / "distance_CST_L.nii.gz", "ab") as changed:
        changed.write(b"\0")  # someone's file now, not the one recorded
    seeds.write_text(seeds.read_text().replace("CST_L", "CST_left"))
    assert stvd.cohort.run(manifest, outdir, serial=True, report=False).failed == []
    assert (outdir / "base" / "distance_CST_L.nii.gz").is_file()


def test_only_leftovers_of_our_killed_writers_are_removed(cohort, tmp_path):
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder)
    outdir = tmp_path / "out"
    (outdir / "base").mkdir(parents=True)
    # A writer killed (SIGKILL) while it staged a map, and a folder named
    # like ours that no run of ours made.
    killed = subprocess.run([sys.executable, "-c", KILLED_WRITER, str(outdir / "base" / "distance_CC_body.nii.gz")],
                            env=dict(os.environ), capture_output=True)
    assert killed.returncode == -signal.SIGKILL, killed.stderr
    leftovers = [p for p in (outdir / "base").iterdir() if p.name.startswith(".stvd-staging-")]
    assert len(leftovers) == 1 and (leftovers[0] / "distance_CC_body.nii.gz").read_bytes() == b"half"
    someone = outdir / "base" / ".stvd-staging-1-1"
    someone.mkdir()
    (someone / "notes.txt").write_text("not stvd's")
    assert stvd.cohort.run(manifest, outdir, serial=True, report=False).failed == []
    assert not leftovers[0].exists()
    assert (someone / "notes.txt").read_text() == "not stvd's"


# --- What a run reads --------------------------------------------------------


def test_a_seed_image_on_a_huge_grid_fails_its_subject_from_its_header(cohort, tmp_path):
    # 800^3 voxels of zeros in half a megabyte, as a subject's seeds.
    import zlib

    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder, seeds="seeds.nii.gz")
    header = nib.Nifti1Header()
    header.set_data_shape((800, 800, 800))
    header.set_data_dtype(np.uint8)
    header.set_qform(np.eye(4), code=1)
    header.set_sform(np.eye(4), code=1)
    header["vox_offset"] = 352

    def member(data):
        compressor = zlib.compressobj(9, zlib.DEFLATED, 31)
        return compressor.compress(data) + compressor.flush()

    zeros = member(bytes(1024000))
    with open(folder / "base" / "seeds.nii.gz", "wb") as bomb:
        bomb.write(member(header.binaryblock + b"\0" * 4))
        for _ in range(500):
            bomb.write(zeros)
    start = time.process_time()
    result = stvd.cohort.run(manifest, tmp_path / "out", serial=True, connectivity=False, report=False)
    seconds = time.process_time() - start
    assert result.failed == ["base"]
    error = result.subjects[0]["error"]
    assert "seeds.nii.gz: the seed labels are on another grid than" in error and "800x800x800" in error, error
    assert seconds < 5, f"{seconds:.1f} s of CPU time"  # read in full, 512 MB and their unique values


def test_a_seeds_table_that_is_a_fifo_fails_its_subject_at_once(cohort, tmp_path):
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder, seeds="seeds.fifo.tsv")
    os.mkfifo(folder / "base" / "seeds.fifo.tsv")
    process = run_cohort_command(manifest, "-o", tmp_path / "out", "--serial", "--no-report", timeout=120)
    assert process.returncode == 3, process.stderr
    table = (tmp_path / "out" / "cohort.tsv").read_text()
    assert "seeds.fifo.tsv: cannot read the seeds: is a FIFO, not a regular file" in table, table


def test_the_cohort_index_reads_no_fifo_and_no_device(cohort, tmp_path):
    # Named report.html in folders of OUTDIR that the index lists.
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder)
    outdir = tmp_path / "out"
    (outdir / "stale").mkdir(parents=True)
    os.mkfifo(outdir / "stale" / "report.html")
    (outdir / "zero").mkdir()
    os.symlink("/dev/zero", outdir / "zero" / "report.html")
    process = run_cohort_command(manifest, "-o", outdir, "--serial", timeout=300)
    assert process.returncode == 0, process.stderr
    assert "./base/report.html" in (outdir / "index.html").read_text()


# --- The manifest ------------------------------------------------------------


@pytest.mark.parametrize("subject, problem", [
    ("index.html", "'index.html' cannot name an output folder: it is the name of a file the run writes next to it"),
    ("Cohort.TSV", "'Cohort.TSV' cannot name an output folder: it is the name of a file the run writes next to it"),
    ("a" * 300, "bytes long, more than the 255 an output folder's name may have here"),
    ("-rf", "'-rf' cannot name an output folder (letters, digits"),
    ("con", "'con' cannot name an output folder (a device name on Windows file systems)"),
    ("s01.", "'s01.' cannot name an output folder (it ends in '.'"),
    ("s01\0x", "'s01\\x00x' cannot name an output folder"),
])
def test_a_subject_id_that_cannot_name_a_folder_everywhere_is_refused_before_any_work(cohort, tmp_path, subject,
                                                                                         problem):
    folder = tmp_path / "study"
    one_subject(cohort, folder)
    manifest = folder / "manifest.tsv"
    rows = manifest.read_text().splitlines()
    other = rows[1]
    manifest.write_text("\n".join([rows[0], other, subject + other[len("base"):]]) + "\n")
    process = run_cohort_command(manifest, "-o", tmp_path / "out")
    assert process.returncode == 2, process.stderr
    if "\0" in subject:
        problem = "row 3, column subject: the cell holds a NUL byte"
    assert process.stderr.count("\n") == 1 and process.stderr.startswith(f"stvd: {manifest}, row 3"), process.stderr
    assert problem in process.stderr, process.stderr
    assert not (tmp_path / "out").exists()


def test_subject_ids_that_differ_only_in_letter_case_are_one_folder(cohort, tmp_path):
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder)
    rows = manifest.read_text().splitlines()
    manifest.write_text("\n".join([rows[0], rows[1], "BASE" + rows[1][4:]]) + "\n")
    process = run_cohort_command(manifest, "-o", tmp_path / "out")
    assert process.returncode == 2
    assert process.stderr == (f"stvd: {manifest}, row 3, column subject: 'BASE' differs from 'base' (row 2) only in "
                              "letter case: one folder on a file system that ignores it\n")
    assert not (tmp_path / "out").exists()


def test_a_nul_byte_in_a_path_is_named_by_row_and_column(cohort, tmp_path):
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder)
    manifest.write_text(manifest.read_text().replace("base/mask.nii.gz", "base/mask\0.nii.gz"))
    process = run_cohort_command(manifest, "-o", tmp_path / "out")
    assert process.returncode == 2
    assert process.stderr == f"stvd: {manifest}, row 2, column mask: the cell holds a NUL byte\n"


def test_a_seed_set_name_too_long_for_its_file_fails_its_subject_in_our_words(cohort, tmp_path):
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder)
    seeds = folder / "base" / "seeds.tsv"
    seeds.write_text(seeds.read_text().replace("CST_L", "C" * 250))
    process = run_cohort_command(manifest, "-o", tmp_path / "out", "--serial", "--no-report")
    assert process.returncode == 3, process.stderr
    error = (tmp_path / "out" / "cohort.tsv").read_text().splitlines()[1].split("\t")[-1]
    assert error.startswith(f"{seeds}, row ") and ", column name: '" in error, error
    assert "is 250 bytes long, more than the 239 an output file's name may have here" in error, error
    assert not (tmp_path / "out" / "base" / "distance_CC_body.nii.gz").exists()


def test_a_link_planted_as_the_lock_file_is_not_followed(cohort, tmp_path):
    # Opening the lock file through a link would create (as root, anywhere)
    # the file it points to.
    folder = tmp_path / "study"
    manifest = one_subject(cohort, folder)
    outdir = tmp_path / "out"
    outdir.mkdir()
    os.symlink(tmp_path / "victim", outdir / ".stvd-cohort.lock")
    process = run_cohort_command(manifest, "-o", outdir, "--serial", "--no-report")
    assert process.returncode == 5, process.stderr
    assert process.stderr == (f"stvd: {outdir}: cannot write the outputs: the lock file .stvd-cohort.lock is a "
                              "symbolic link, which stvd does not follow\n")
    assert not (tmp_path / "victim").exists()
