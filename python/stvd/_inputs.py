"""Inputs as the caller gives them (paths, NiBabel images, NumPy arrays,
lists), turned into what the extension module takes."""

import os
import warnings

import numpy as np

from . import _core

try:
    import nibabel
except ImportError:  # the package works on paths and arrays without NiBabel
    nibabel = None


def is_image(value):
    """Whether ``value`` is a NiBabel image."""
    return nibabel is not None and isinstance(value, nibabel.spatialimages.SpatialImage)


def is_path(value):
    return isinstance(value, (str, os.PathLike))


def image_name(image, default):
    """The file an image was loaded from, for messages; ``default`` otherwise."""
    filename = image.get_filename()
    return filename if filename else default


def image_zooms(image):
    """The voxel sizes of the first three axes, as the header stores them."""
    return tuple(float(z) for z in image.header.get_zooms()[:3])


def scalar_image_spec(value, name):
    """A mask or label image, a path, a NiBabel image or an array, as the
    extension takes it: the path, or a tuple ``(array, affine, zooms, name)``
    (an array without an affine is taken to be on the tensors' grid when its
    shape is theirs); ``name`` names it in messages unless a file does. A
    NiBabel image's data stay unread (its lazy ``dataobj``) until its grid
    has been compared with the tensors': a small .nii.gz can declare a grid
    of billions of voxels."""
    if value is None:
        return None
    if is_path(value):
        return os.fspath(value)
    if is_image(value):
        return (value.dataobj, value.affine, image_zooms(value), image_name(value, name))
    return (value, None, None, name)


def tensor_field(tensors, affine, mask, options):
    """The extension's TensorField for a path, a NiBabel image or an array;
    what the readers noted about the files becomes a warning, as the tool
    prints it."""
    field = _tensor_field(tensors, affine, mask, options)
    for line in field.warnings:
        warnings.warn("stvd: " + line, stacklevel=4)
    return field


def _tensor_field(tensors, affine, mask, options):
    mask_spec = scalar_image_spec(mask, "mask")
    if is_path(tensors):
        if affine is not None:
            raise ValueError("affine= applies to arrays; a file has its own geometry")
        return _core.TensorField.from_file(os.fspath(tensors), mask=mask_spec, **options)
    if is_image(tensors):
        if affine is not None:
            raise ValueError("affine= applies to arrays; a NiBabel image has its own")
        header = tensors.header
        intent = getattr(header, "get_intent", None)
        symmatrix = intent is not None and intent()[0] == "symmetric matrix"
        return _core.TensorField.from_array(
            np.asanyarray(tensors.dataobj), tensors.affine, zooms=image_zooms(tensors), nifti_intent=symmatrix,
            name=image_name(tensors, "tensors"), mask=mask_spec, **options)
    if tensors is None:
        raise TypeError("tensors: expected a path, a NiBabel image or an array, got None")
    if affine is None:
        raise ValueError("tensors: an array needs affine=, the 4x4 matrix from voxel indices to RAS millimetres")
    return _core.TensorField.from_array(tensors, affine, mask=mask_spec, **options)


def _triples(value, name, expected):
    """One triple or a sequence of them as an (N, 3) array; None when there
    is none. `expected` names the triples in the message for another shape."""
    if value is None:
        return None
    array = np.asarray(value)
    if array.ndim == 1 and array.shape[0] == 3:
        array = array[np.newaxis]
    if array.size == 0:
        return None
    if array.ndim != 2 or array.shape[1] != 3:
        raise ValueError(f"{name}: expected {expected}, got an array of shape {array.shape}")
    return array


def voxel_list(value, name, points_keyword):
    """Voxel indices as a list of (i, j, k): one triple or a sequence of them.
    Floating-point numbers are refused, whole or not: DIPY and
    nibabel.streamlines give seeds as float points in world millimetres,
    which belong in ``points_keyword`` (``seed_points=``), and taking such a
    point as a voxel index would start from another place without a word."""
    array = _triples(value, name, "(i, j, k) voxel indices")
    if array is None:
        return []
    if array.dtype.kind == "f":
        whole = bool(np.all(np.isfinite(array)) and np.all(array == np.round(array)))
        raise TypeError(
            f"{name}: voxel indices must be integers, got {'whole ' if whole else ''}floating-point numbers "
            f"(dtype {array.dtype}); points in world millimetres (RAS+, the frame of the image's affine, as DIPY "
            f"and nibabel.streamlines give them) go to {points_keyword}=, voxel indices as integers "
            f"({name}=np.asarray(...).astype(int) if they are indices)")
    if array.dtype.kind not in "iu":
        raise TypeError(f"{name}: voxel indices must be integers, got dtype {array.dtype}")
    limit = np.iinfo(np.int32)
    if array.min() < limit.min or array.max() > limit.max:
        raise ValueError(f"{name}: a voxel index is out of the 32-bit range")
    return [tuple(int(c) for c in row) for row in array]


def index_list(value, name):
    """Vertex indices as a list of ints: one index or a sequence of them."""
    array = np.atleast_1d(np.asarray(value))
    if array.ndim != 1:
        raise ValueError(f"{name}: expected vertex indices, got an array of shape {array.shape}")
    if array.size and array.dtype.kind not in "iu":
        raise TypeError(f"{name}: vertex indices must be integers, got dtype {array.dtype}")
    return [int(v) for v in array]


def point_list(value, name):
    """Physical points as a list of (x, y, z) in millimetres."""
    array = _triples(value, name, "(x, y, z) points in millimetres")
    if array is None:
        return []
    if array.dtype.kind not in "iuf":
        raise TypeError(f"{name}: expected numbers, got dtype {array.dtype}")
    array = array.astype(np.float64)
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name}: a point is not finite")
    return [tuple(row) for row in array]
