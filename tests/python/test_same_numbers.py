"""NumPy arrays, NiBabel images, paths and the `stvd` tool give the same
distance maps, bit for bit: the same reading, the same metric, the same
options."""

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import (CC_BODY, CC_BODY_RAS, CST_L, DIPY_5D, FA, FSL_6, MASK, TEEM, tool_distance)


def identical(a, b):
    """Equal bit for bit, as float32 maps (the unreachable value included)."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.dtype == b.dtype == np.float32
    assert a.shape == b.shape
    assert np.array_equal(a.view(np.uint32), b.view(np.uint32)), \
        f"{np.count_nonzero(a != b)} voxels differ, by at most {np.nanmax(np.abs(a - b))}"
    return True


def test_the_default_run_is_the_tools_from_a_path_an_image_and_an_array(tmp_path, dipy_image, dipy_components):
    tool = tool_distance(tmp_path, DIPY_5D, "--seed-voxel", "55,54,15")
    assert np.count_nonzero(tool >= 0) == 132892  # the whole brain is reached

    from_path = stvd.distance(str(DIPY_5D), [CC_BODY])
    from_image = stvd.distance(dipy_image, [CC_BODY])
    from_array = stvd.distance(dipy_components, [CC_BODY], affine=dipy_image.affine, tensor_order="lower")
    assert identical(from_path.get_fdata(dtype=np.float32), tool)
    assert identical(np.asanyarray(from_image.dataobj), tool)
    assert identical(np.asanyarray(from_array.dataobj), tool)
    assert np.array_equal(from_array.affine, dipy_image.affine)  # an array with affine= gives an image too


def test_an_image_in_gives_an_image_on_its_grid(dipy_image):
    out = stvd.distance(dipy_image, CC_BODY)
    assert isinstance(out, nib.Nifti1Image)
    assert out.shape == dipy_image.shape[:3]
    assert out.get_data_dtype() == np.float32
    assert np.array_equal(out.affine, dipy_image.affine)
    assert out.header.get_intent()[0] == "none"
    assert out.header.get_zooms() == dipy_image.header.get_zooms()[:3]


def test_the_grid_from_an_image_is_the_one_itk_reads_from_its_file(dipy_image):
    """The geometry the library reads through ITK from the file, and the one
    it makes from NiBabel's affine and zooms, agree to the last bit."""
    through_itk = stvd.propagate(str(DIPY_5D), CC_BODY)
    through_nibabel = stvd.propagate(dipy_image, CC_BODY)
    assert np.array_equal(through_itk.affine, through_nibabel.affine)
    assert through_itk.zooms == through_nibabel.zooms
    assert np.array_equal(through_itk.distance, through_nibabel.distance)
    # The RAS affine the library reports is NiBabel's to rounding of the
    # single-precision pixdim against the columns' lengths.
    assert np.allclose(through_itk.affine, dipy_image.affine, rtol=0, atol=1e-6)


def test_any_memory_order_and_the_matrix_form_give_the_same_numbers(dipy_image, dipy_components):
    def distance(*args, **keywords):
        return np.asanyarray(stvd.distance(*args, **keywords).dataobj)

    reference = distance(dipy_components, CC_BODY, affine=dipy_image.affine, tensor_order="lower")
    c_order = np.ascontiguousarray(dipy_components, dtype=np.float64)
    assert identical(distance(c_order, CC_BODY, affine=dipy_image.affine, tensor_order="lower"), reference)
    xx, xy, yy, xz, yz, zz = np.moveaxis(dipy_components, -1, 0)
    matrices = np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1), np.stack([xz, yz, zz], -1)], -2)
    assert matrices.shape == dipy_components.shape[:3] + (3, 3)
    assert identical(distance(matrices, CC_BODY, affine=dipy_image.affine), reference)
    fsl = dipy_components[..., [0, 1, 3, 2, 4, 5]]
    assert identical(distance(fsl, CC_BODY, affine=dipy_image.affine, tensor_order="fsl"), reference)


@pytest.mark.parametrize("tool_options, keywords", [
    (["--method", "dijkstra"], dict(method="dijkstra")),
    (["--k", "3", "--chain-measure", "projection", "--stencil", "98"],
     dict(k=3, chain_measure="projection", stencil="98")),
    (["--diffusion-metric", "adjugate", "--max-anisotropy", "20", "--fa-threshold", "0.2"],
     dict(diffusion_metric="adjugate", max_anisotropy=20, fa_threshold=0.2)),
    (["--max-distance", "30", "--unreachable-value", "nan"], dict(max_distance=30, unreachable_value=np.nan)),
    # DIPY's voxel-frame components read as RAS ones are a wrong frame on
    # purpose (this LAS brain: flipped along i), which the frame check stops
    # in both unless accepted (tests/python/test_tensor_frame.py).
    (["--tensor-frame", "world", "--accept-misaligned-tensors"],
     dict(tensor_frame="world", accept_misaligned_tensors=True)),
    (["--fa-threshold", "0.2", "--domain-connectivity", "26"], dict(fa_threshold=0.2, domain_connectivity=26)),
    (["--fa-threshold", "0.2", "--domain-connectivity", "18", "--method", "dijkstra", "--stencil", "18"],
     dict(fa_threshold=0.2, domain_connectivity=18, method="dijkstra", stencil="18")),
])
def test_options_give_the_tools_numbers(tmp_path, dipy_image, tool_options, keywords):
    tool = tool_distance(tmp_path, DIPY_5D, "--seed-voxel", "55,54,15", *tool_options)
    ours = stvd.distance(dipy_image, CC_BODY, **keywords)
    assert identical(np.asanyarray(ours.dataobj), tool)


def test_seeds_as_points_labels_and_a_mask_give_the_tools_numbers(tmp_path, dipy_image):
    labels = np.zeros(dipy_image.shape[:3], np.int16)
    labels[66:71, 48:53, 9:14] = 3  # around CST_L
    labels_path = tmp_path / "labels.nii.gz"
    nib.save(nib.Nifti1Image(labels, dipy_image.affine), labels_path)
    tool = tool_distance(tmp_path, DIPY_5D, "--seed-point", ",".join(map(str, CC_BODY_RAS)), "--seeds", labels_path,
                         "--mask", MASK)
    mask = nib.load(MASK)
    # Each as an array, a path and an image.
    for seed_labels, given_mask in zip((labels, labels_path, nib.load(labels_path)),
                                       (mask, np.asanyarray(mask.dataobj), MASK)):
        ours = stvd.distance(dipy_image, seed_points=[CC_BODY_RAS], seed_labels=seed_labels, mask=given_mask)
        assert identical(np.asanyarray(ours.dataobj), tool)


def test_the_six_volume_file_through_nibabel_needs_its_order_and_then_gives_the_tools_numbers(tmp_path):
    image = nib.load(FSL_6)
    with pytest.raises(ValueError, match="does not say its component order"):
        stvd.distance(image, CC_BODY)
    tool = tool_distance(tmp_path, FSL_6, "--seed-voxel", "55,54,15", "--tensor-order", "fsl")
    assert identical(np.asanyarray(stvd.distance(image, CC_BODY, tensor_order="fsl").dataobj), tool)


def test_the_nrrd_file_by_path_gives_the_tools_numbers(tmp_path):
    tool = tool_distance(tmp_path, TEEM, "--seed-voxel", "68,50,11", name="teem.nii.gz")
    ours = stvd.distance(str(TEEM), CST_L)
    assert isinstance(ours, nib.Nifti1Image)
    assert identical(np.asanyarray(ours.dataobj), tool)


def test_the_lanthier_method_gives_the_tools_numbers(tmp_path, dipy_image):
    tool = tool_distance(tmp_path, DIPY_5D, "--seed-voxel", "55,54,15", "--method", "lanthier", "--steiner", "1",
                         "--max-distance", "12")
    ours = stvd.distance(dipy_image, CC_BODY, method="lanthier", steiner=1, max_distance=12)
    assert identical(np.asanyarray(ours.dataobj), tool)


def test_the_lower_level_result_holds_the_distances_predecessors_and_statistics(dipy_image):
    result = stvd.propagate(dipy_image, CC_BODY)
    assert result.distance.dtype == np.float64 and result.distance.shape == dipy_image.shape[:3]
    assert not result.distance.flags.writeable
    assert result.distance[CC_BODY] == 0.0
    assert result.predecessor[CC_BODY] == stvd.NO_VERTEX
    reached = np.isfinite(result.distance)
    assert np.count_nonzero(reached) == result.finalized_vertices == result.voxel_counts["domain"] == 132892
    # Every predecessor chain ends at the seed.
    predecessor = result.predecessor.ravel(order="F")
    seed = np.ravel_multi_index(CC_BODY, result.shape, order="F")
    chain_end = np.flatnonzero(reached.ravel(order="F"))
    for _ in range(10000):
        step = predecessor[chain_end]
        chain_end = np.where(step == stvd.NO_VERTEX, chain_end, step)
        if np.all(step == stvd.NO_VERTEX):
            break
    assert np.all(chain_end == seed)
    assert result.termination == "completed"
    assert (result.method, result.k, result.chain_measure, result.stencil) == (
        stvd.defaults.method, stvd.defaults.k, stvd.defaults.chain_measure, stvd.defaults.stencil)
    assert result.relaxed_edges > result.finalized_vertices
    assert np.array_equal(result.seeds, [CC_BODY])
    fa = nib.load(FA).get_fdata()
    assert np.allclose(result.fractional_anisotropy[reached], fa[reached], atol=1e-5)
