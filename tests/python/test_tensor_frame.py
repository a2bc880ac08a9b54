"""The tensor frame check from Python (docs/python.md, "Reoriented tensor
images"): NiBabel's as_closest_canonical reorders a tensor image's voxels
and keeps its components, which then no longer match the image axes. A run
stops with a ValueError naming the flip that fits (as the tool stops with
exit code 3), accept_misaligned_tensors=True goes on, and
stvd.check_tensor_frame reports the frame, from a file, a NiBabel image and
an array alike; volumes without evidence never stop a run."""

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import CC_BODY, DIPY_5D, MASK


@pytest.fixture(scope="module")
def canonical():
    """The shipped brain (LAS) as nib.as_closest_canonical makes it: RAS
    voxel order, the same components."""
    image = nib.as_closest_canonical(nib.load(DIPY_5D))
    assert nib.aff2axcodes(image.affine) == ("R", "A", "S")
    return image


def test_the_shipped_brain_fits_as_read_from_a_file_an_image_and_an_array():
    image = nib.load(DIPY_5D)
    lower = np.asanyarray(image.dataobj)[:, :, :, 0, :]
    for tensors, keywords in ((DIPY_5D, {}), (image, {}), (lower, {"affine": image.affine, "tensor_order": "lower"})):
        check = stvd.check_tensor_frame(tensors, mask=MASK, **keywords)
        assert check["verdict"] == "consistent", check["summary"]
        assert check["best"] == "(i, j, k)" and check["margin"] > 1.3
        assert len(check["mean_length_mm"]) == 24 and check["seeds"] == 2000


def test_a_wrong_tensor_frame_that_flips_an_axis_is_detected():
    # DIPY's voxel-frame components read as RAS (world) ones: for this LAS
    # brain the same as flipping i (up to its 5.7 degrees of obliquity).
    check = stvd.check_tensor_frame(DIPY_5D, tensor_frame="world")
    assert check["verdict"] == "mismatch" and check["best"] == "(-i, j, k)", check["summary"]
    with pytest.raises(ValueError, match="flipped along i"):
        stvd.distance(DIPY_5D, CC_BODY, tensor_frame="world")


def test_as_closest_canonical_is_detected_and_the_flip_named(canonical):
    # Before: accepted, and distances off by a median 3.6 %, up to 74 %.
    with pytest.raises(ValueError) as caught:
        stvd.distance(canonical, (111 - CC_BODY[0], CC_BODY[1], CC_BODY[2]))
    message = str(caught.value)
    assert "\n" not in message
    assert "flipped along i (-i, j, k)" in message and "accept_misaligned_tensors=True" in message
    assert "--" not in message  # keyword names, not flags
    check = stvd.check_tensor_frame(canonical)
    assert check["verdict"] == "mismatch" and check["best"] == "(-i, j, k)" and check["ratio"] > 1.5
    # Going on is the user's choice, and the check stays on the record.
    result = stvd.propagate(canonical, (111 - CC_BODY[0], CC_BODY[1], CC_BODY[2]), accept_misaligned_tensors=True)
    assert result.tensor_info["frame_check"]["verdict"] == "mismatch"
    # The components flipped along i as the message says: the distances of
    # the file as it was, voxel for voxel (the first axis counted the other way).
    data = np.asanyarray(canonical.dataobj).copy()
    data[..., 1] *= -1  # xy
    data[..., 3] *= -1  # xz
    fixed = nib.Nifti1Image(data, canonical.affine, canonical.header)
    repaired = stvd.distance(fixed, (111 - CC_BODY[0], CC_BODY[1], CC_BODY[2]), method="dijkstra")
    original = stvd.distance(DIPY_5D, CC_BODY, method="dijkstra")
    np.testing.assert_allclose(np.asanyarray(repaired.dataobj)[::-1], np.asanyarray(original.dataobj), atol=1e-3)


def test_volumes_without_evidence_never_stop_a_run():
    affine = np.diag([2.0, 2.0, 2.0, 1.0])
    # A tiny phantom: one tract along i.
    tiny = np.zeros((6, 6, 6, 6), np.float32)
    tiny[..., 0], tiny[..., 2], tiny[..., 5] = 3.0, 1.0, 1.0
    assert stvd.check_tensor_frame(tiny, affine=affine, tensor_order="lower")["verdict"] != "mismatch"
    stvd.distance(tiny, (1, 1, 1), affine=affine, tensor_order="lower")
    # Noise: anisotropic tensors in random directions.
    random = np.random.default_rng(31)
    e = random.normal(size=(24, 24, 24, 3))
    e /= np.linalg.norm(e, axis=-1, keepdims=True)
    matrices = 0.3 * np.eye(3) + 1.7 * e[..., :, None] * e[..., None, :]
    check = stvd.check_tensor_frame(matrices, affine=affine)
    assert check["verdict"] != "mismatch", check["summary"]
    stvd.distance(matrices, (12, 12, 12), affine=affine)
    # Metric tensors are not checked (their principal direction is the costly one).
    assert stvd.propagate(tiny, (1, 1, 1), affine=affine, tensor_order="lower",
                          tensor_kind="metric").tensor_info["frame_check"]["verdict"] == "not checked"
