"""The package keeps the conventions of the libraries it sits between:
distance maps are NiBabel images whenever an affine is known, results go
through pickle (Dask, multiprocessing), paths merge into one set that
NiBabel saves, and every call that takes an array takes its affine."""

import multiprocessing
import pickle

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import CC_BODY, CC_BODY_L_LATERAL, CC_BODY_R_LATERAL, CST_L, DIPY_5D, MASK

# A small oblique grid with a constant metric: quick, and its affine is not
# the identity, so a dropped or rebuilt affine shows.
SHAPE = (9, 8, 7)
ANGLE = np.deg2rad(20)
AFFINE = np.array([[1.2 * np.cos(ANGLE), -1.5 * np.sin(ANGLE), 0, -4.0],
                   [1.2 * np.sin(ANGLE), 1.5 * np.cos(ANGLE), 0, 7.5],
                   [0, 0, 2.0, -3.25],
                   [0, 0, 0, 1]])


def small_tensors():
    t = np.zeros(SHAPE + (6,), np.float32)
    t[..., 0], t[..., 2], t[..., 5] = 2.0, 1.0, 0.5  # 'lower': xx, xy, yy, xz, yz, zz
    return t


def small_propagation(**keywords):
    return stvd.propagate(small_tensors(), (2, 2, 2), affine=AFFINE, tensor_order="lower", tensor_kind="metric",
                          **keywords)


# --- distance maps are images whenever an affine is known (issue 31, item 7)

def test_an_array_with_an_affine_gives_an_image_with_that_affine(tmp_path):
    result = small_propagation()
    image = result.distance_map()
    assert isinstance(image, nib.Nifti1Image)
    assert np.array_equal(image.affine, AFFINE)
    assert image.get_data_dtype() == np.float32
    expected = np.where(np.isfinite(result.distance), result.distance, stvd.defaults.unreachable_value)
    assert np.array_equal(np.asanyarray(image.dataobj), expected.astype(np.float32))
    # nib.save takes it, and the file holds the grid and the values.
    nib.save(image, tmp_path / "d.nii.gz")
    back = nib.load(tmp_path / "d.nii.gz")
    assert np.allclose(back.affine, AFFINE, atol=1e-6)
    assert np.array_equal(np.asanyarray(back.dataobj), np.asanyarray(image.dataobj))
    # stvd.distance returns the same.
    direct = stvd.distance(small_tensors(), (2, 2, 2), affine=AFFINE, tensor_order="lower", tensor_kind="metric")
    assert isinstance(direct, nib.Nifti1Image) and np.array_equal(direct.affine, AFFINE)
    assert np.array_equal(np.asanyarray(direct.dataobj), np.asanyarray(image.dataobj))


def test_images_and_files_keep_their_affine(dipy_image):
    for given in (dipy_image, str(DIPY_5D)):
        image = stvd.propagate(given, CC_BODY, max_distance=5).distance_map()
        assert isinstance(image, nib.Nifti1Image)
        assert np.array_equal(image.affine, dipy_image.affine)

