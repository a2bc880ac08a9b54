"""What the package writes, it writes as the `stvd` tool does
(docs/reliability.md): never over an input, however the two are spelled
(another path to the same file, a symbolic link, a hard link), never two
outputs into one file, all outputs or none, and the tool's bytes."""

import filecmp
import hashlib
import os

import nibabel as nib
import numpy as np
import pytest
import stvd
from conftest import CC_BODY, CST_L, DIPY_5D, MASK, run_tool


def digest(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


@pytest.fixture()
def inputs(tmp_path):
    """Copies of the tensors and the mask in a folder of their own, and a
    label image with two regions, so that a failed test cannot harm the
    shipped data."""
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / "t.nii.gz").write_bytes(DIPY_5D.read_bytes())
    (folder / "mask.nii.gz").write_bytes(MASK.read_bytes())
    mask = nib.load(MASK)
    labels = np.zeros(mask.shape, dtype=np.int16)
    labels[CC_BODY] = 1
    labels[CST_L] = 2
    nib.save(nib.Nifti1Image(labels, mask.affine), folder / "labels.nii.gz")
    return folder


def refuses(call, *roles):
    """Runs call(); it must raise FileConflictError (a ValueError) in one
    line naming both roles."""
    with pytest.raises(stvd.FileConflictError) as raised:
        call()
    message = str(raised.value)
    assert isinstance(raised.value, ValueError) and "\n" not in message
    for role in roles:
        assert role in message, message
    return message


def nothing_staged(folder):
    return not [name for name in os.listdir(folder) if name.startswith(".stvd-staging")]


def test_a_distance_map_is_never_written_over_an_input(inputs, monkeypatch):
    before = {name: digest(inputs / name) for name in ("t.nii.gz", "mask.nii.gz", "labels.nii.gz")}
    result = stvd.propagate(inputs / "t.nii.gz", mask=nib.load(inputs / "mask.nii.gz"),
                            seed_labels=str(inputs / "labels.nii.gz"))
    assert [role for role, _ in result.input_files] == ["tensor input", "mask", "seed labels"]
    refuses(lambda: result.save(inputs / "t.nii.gz"), "distance map", "tensor input")
    refuses(lambda: result.save(inputs / "mask.nii.gz"), "distance map", "mask")  # a NiBabel image: its file
    refuses(lambda: result.save(inputs / "labels.nii.gz"), "distance map", "seed labels")
    # Another spelling, a symbolic link and a hard link are the same file.
    monkeypatch.chdir(inputs)
    refuses(lambda: result.save("./../in/t.nii.gz"), "distance map", "tensor input")
    os.symlink(inputs / "t.nii.gz", inputs / "link.nii.gz")
    refuses(lambda: result.save(inputs / "link.nii.gz"), "distance map", "tensor input")
    os.link(inputs / "mask.nii.gz", inputs / "hard.nii.gz")
    refuses(lambda: result.save(inputs / "hard.nii.gz"), "distance map", "mask")
    assert before == {name: digest(inputs / name) for name in before}
    assert nothing_staged(inputs)


def test_an_input_reached_through_a_symbolic_link_is_protected(inputs):
    os.symlink(inputs / "t.nii.gz", inputs / "link.nii.gz")
    result = stvd.propagate(inputs / "link.nii.gz", CC_BODY)
    refuses(lambda: result.save(inputs / "t.nii.gz"), "distance map", "tensor input")


def test_paths_are_never_written_over_an_input(inputs):
    result = stvd.propagate(str(inputs / "t.nii.gz"), CC_BODY)
    paths = stvd.trace_paths(result, target_labels=inputs / "labels.nii.gz")
    refuses(lambda: paths.save(inputs / "labels.nii.gz"), "paths file", "target labels")
    refuses(lambda: paths.save(inputs / "t.nii.gz"), "paths file", "tensor input")


def test_two_outputs_that_are_one_file_are_refused(tmp_path):
    (tmp_path / "sub").mkdir()
    refuses(lambda: stvd.OutputFiles({"table": tmp_path / "a.csv", "copy": tmp_path / "sub" / ".." / "a.csv"}),
            "table", "copy")
    assert not (tmp_path / "a.csv").exists()


def test_outputs_appear_together_or_not_at_all(tmp_path):
    (tmp_path / "old.txt").write_text("kept")
    with pytest.raises(RuntimeError, match="the second writer failed"):
        with stvd.OutputFiles({"first": tmp_path / "new.txt", "second": tmp_path / "old.txt"}) as out:
            out.write(tmp_path / "new.txt", lambda staging: open(staging, "w").write("new"))

            def fail(staging):
                open(staging, "w").write("half")
                raise RuntimeError("the second writer failed")

            out.write(tmp_path / "old.txt", fail)
    assert not (tmp_path / "new.txt").exists()
    assert (tmp_path / "old.txt").read_text() == "kept"
    assert nothing_staged(tmp_path)
    with stvd.OutputFiles({"first": tmp_path / "new.txt"}) as out:
        out.write(tmp_path / "new.txt", lambda staging: open(staging, "w").write("new"))
        assert not (tmp_path / "new.txt").exists()  # staged until the block ends
    assert (tmp_path / "new.txt").read_text() == "new"


def test_an_output_that_cannot_be_written_is_an_os_error_before_any_work(tmp_path):
    with pytest.raises(stvd.OutputError, match="missing"):
        stvd.OutputFiles({"distance map": tmp_path / "missing" / "d.nii.gz"})
    assert issubclass(stvd.OutputError, OSError)


def test_saved_files_are_the_tools_bytes(tmp_path):
    voxel = ",".join(map(str, CC_BODY))
    result = stvd.propagate(DIPY_5D, CC_BODY)
    result.save(tmp_path / "ours.nii.gz")
    run_tool("distance", DIPY_5D, "--seed-voxel", voxel, "-o", tmp_path / "tool.nii.gz", "-q")
    assert filecmp.cmp(tmp_path / "ours.nii.gz", tmp_path / "tool.nii.gz", shallow=False)
    paths = stvd.trace_paths(result, CST_L)
    for extension in ("tck", "trk", "vtk"):
        paths.save(tmp_path / f"ours.{extension}")
        run_tool("path", DIPY_5D, "--seed-voxel", voxel, "--target-voxel", ",".join(map(str, CST_L)), "-o",
                 tmp_path / f"tool.{extension}", "-q")
        assert filecmp.cmp(tmp_path / f"ours.{extension}", tmp_path / f"tool.{extension}", shallow=False), extension


def test_an_output_set_holds_a_distance_map_and_the_callers_own_files(tmp_path):
    result = stvd.propagate(DIPY_5D, CC_BODY)
    outputs = {"distance map": tmp_path / "d.nii.gz", "summary": tmp_path / "summary.txt"}
    with stvd.OutputFiles(outputs, inputs=result.input_files) as out:
        result.save(tmp_path / "d.nii.gz", outputs=out)
        out.write(tmp_path / "summary.txt", lambda staging: open(staging, "w").write("reached\n"))
    assert (tmp_path / "d.nii.gz").exists() and (tmp_path / "summary.txt").exists()
    # A set that was not told the propagation's inputs cannot take its map.
    with pytest.raises(ValueError, match="input_files"):
        with stvd.OutputFiles({"distance map": tmp_path / "e.nii.gz"}) as out:
            result.save(tmp_path / "e.nii.gz", outputs=out)
    assert not (tmp_path / "e.nii.gz").exists()
