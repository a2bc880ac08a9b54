"""Arrays and side inputs the package reads exactly or refuses: every NumPy
element type the bindings take is read as the numbers it holds (bool, every
integer width, float16, float32, float64, either byte order, any strides,
unaligned), and the others are refused with a TypeError (extended
precision, complex, object); a numpy.ma masked array's mask is honoured
(its masked voxels are outside the domain, in no region); a side input (a mask, seed or
target labels, a label image) on another grid is refused from its header,
before its data are read, and a gzip stream is read only as far as its
header needs (docs/reliability.md, "Security")."""

import time
import zlib

import nibabel as nib
import numpy as np
import pytest

import stvd

SHAPE = (12, 10, 8)
AFFINE = np.diag([1.0, 1.5, 2.0, 1.0])
SEED = (2, 2, 2)


def tensors(dtype=np.float32):
    """A constant metric, six components per voxel in the 'lower' order."""
    t = np.zeros(SHAPE + (6,), dtype)
    t[..., 0], t[..., 2], t[..., 5] = 2.0, 1.0, 0.5
    return t


def distances(values=None, **keywords):
    image = stvd.distance(tensors() if values is None else values, SEED, affine=AFFINE, tensor_order="lower",
                          tensor_kind="metric", **keywords)
    return np.asanyarray(image.dataobj)


def mask_values():
    mask = np.zeros(SHAPE)
    mask[:8, :, :] = 1.0
    mask[3, 4, 5] = 0.0  # one hole
    return mask


def labels_values():
    labels = np.zeros(SHAPE, np.int64)
    labels[1:3, 1:3, 1:3] = 1
    labels[8:10, 6:8, 4:6] = 2 ** 40 + 7  # beyond float32's integers
    return labels


def strided(array):
    """The same values in a larger buffer, every other element."""
    wide = np.zeros((SHAPE[0] * 2,) + SHAPE[1:], array.dtype)
    wide[::2] = array
    return wide[::2]


def unaligned(array):
    """The same values at an odd address."""
    raw = np.zeros(array.nbytes + 1, np.uint8)
    view = raw[1:].view(array.dtype).reshape(array.shape)
    view[...] = array
    assert not view.flags.aligned
    return view


def structured_field(array):
    """The same values as a field of a structured array (strides that are
    not a multiple of the element size)."""
    record = np.zeros(array.shape, dtype=[("flag", "u1"), ("value", array.dtype)])
    record["value"] = array
    return record["value"]


def test_masks_of_every_type_read_exactly_give_the_same_domain():
    mask = mask_values()
    reference = distances(mask=mask.astype(np.uint8))
    assert reference[10, 0, 0] == -1 and reference[3, 4, 5] == -1 and reference[4, 4, 4] > 0  # outside, inside
    variants = {"bool": mask.astype(bool), "float16": mask.astype(np.float16), "float32": mask.astype(np.float32),
                "big-endian float64": mask.astype(">f8"), "big-endian int16": mask.astype(">i2"),
                "uint64": mask.astype(np.uint64), "Fortran order": np.asfortranarray(mask),
                "reversed twice": mask[::-1][::-1], "strided": strided(mask), "unaligned": unaligned(mask),
                "structured field": structured_field(mask)}
    for name, variant in variants.items():
        np.testing.assert_array_equal(distances(mask=variant), reference, err_msg=name)


def test_labels_of_every_integer_type_are_the_same_regions():
    labels = labels_values()
    reference = stvd.connectivity(tensors(), labels, affine=AFFINE, tensor_order="lower", tensor_kind="metric",
                                  threads=1)
    assert list(reference.labels) == [1, 2 ** 40 + 7]
    for name, variant in {"big-endian int64": labels.astype(">i8"), "uint64": labels.astype(np.uint64),
                          "strided": strided(labels), "unaligned": unaligned(labels)}.items():
        result = stvd.connectivity(tensors(), variant, affine=AFFINE, tensor_order="lower", tensor_kind="metric",
                                   threads=1)
        assert list(result.labels) == list(reference.labels), name
        np.testing.assert_array_equal(result.geodesic_mm, reference.geodesic_mm, err_msg=name)


def test_tensors_in_half_precision_or_the_other_byte_order_are_the_same_tensors():
    reference = distances()
    for name, values in {"float16": tensors(np.float16), "big-endian float32": tensors(">f4"),
                         "float64": tensors(np.float64), "unaligned": unaligned(tensors())}.items():
        np.testing.assert_array_equal(distances(values), reference, err_msg=name)


@pytest.mark.parametrize("kind", ["longdouble", "complex", "object"])
def test_element_types_not_read_exactly_are_refused_in_every_role(kind):
    # Extended precision was read as float64 through 16-byte strides: another
    # domain, and another from run to run; rounded to float64 a mask of
    # 1e-4940 would lose its voxels.
    def convert(array):
        if kind == "longdouble":
            return array.astype(np.longdouble)
        if kind == "complex":
            return array.astype(np.complex128)
        return array.astype(object)

    expected = {"longdouble": "not read exactly", "complex": "complex", "object": "dtype object"}[kind]
    calls = {
        "mask": lambda: distances(mask=convert(mask_values())),
        "seed labels": lambda: stvd.distance(tensors(), seed_labels=convert(labels_values() == 1), affine=AFFINE,
                                             tensor_order="lower", tensor_kind="metric"),
        "labels": lambda: stvd.connectivity(tensors(), convert(labels_values()), affine=AFFINE, tensor_order="lower",
                                            tensor_kind="metric", threads=1),
        "tensors": lambda: distances(convert(tensors(np.float64))),
    }
    for role, call in calls.items():
        with pytest.raises(TypeError) as caught:
            call()
        assert expected in str(caught.value), f"{role}: {caught.value}"
        assert "\n" not in str(caught.value)


def test_a_masked_arrays_masked_voxels_are_outside_the_domain_in_every_role():
    # numpy.ma was refused (issue 29), and before that its mask was dropped
    # (69,604 voxels reached in the "masked" half of a brain). Now a masked
    # voxel is what a zero in mask= makes it: outside the domain, whatever
    # values lie under the mask (NaN here), and in no seed or label region.
    outside = mask_values() == 0
    reference = distances(mask=mask_values())
    assert (reference[outside] == -1).all() and (reference[~outside] >= 0).all()

    masked_tensors = np.ma.masked_array(tensors(np.float64), mask=np.broadcast_to(outside[..., None], SHAPE + (6,)))
    masked_tensors.data[outside] = np.nan  # garbage under the mask is never read
    np.testing.assert_array_equal(distances(masked_tensors), reference)
    # One masked component is enough to leave the voxel out.
    one_component = np.zeros(SHAPE + (6,), bool)
    one_component[..., 3] = outside
    np.testing.assert_array_equal(distances(np.ma.masked_array(tensors(), mask=one_component)), reference)
    # A masked array with nothing masked is its values.
    np.testing.assert_array_equal(distances(np.ma.masked_array(tensors())), distances())

    # mask=: masked entries are outside, even where the value under them is 1.
    ones = np.ma.masked_array(np.ones(SHAPE), mask=outside)
    np.testing.assert_array_equal(distances(mask=ones), reference)
    # Both masks together: the voxels either leaves out.
    half = np.zeros(SHAPE, bool)
    half[:, 6:, :] = True
    both = distances(masked_tensors, mask=np.ma.masked_array(np.ones(SHAPE), mask=half))
    assert (both[half | outside] == -1).all() and (both[~(half | outside)] >= 0).all()

    # Seed labels: a masked voxel is no seed.
    seeds = np.zeros(SHAPE, np.uint8)
    seeds[2, 2, 2] = seeds[6, 6, 6] = 1
    only_first = np.ma.masked_array(seeds, mask=np.zeros(SHAPE, bool))
    only_first.mask[6, 6, 6] = True
    from_labels = stvd.distance(tensors(), seed_labels=only_first, affine=AFFINE, tensor_order="lower",
                                tensor_kind="metric")
    np.testing.assert_array_equal(np.asanyarray(from_labels.dataobj), distances())

    # Label images: a masked voxel belongs to no region.
    labels = labels_values()
    labels[5:7, 1:3, 5:7] = 3
    without_second = np.ma.masked_array(labels, mask=labels == 2 ** 40 + 7)
    result = stvd.connectivity(tensors(), without_second, affine=AFFINE, tensor_order="lower", tensor_kind="metric",
                               threads=1)
    assert list(result.labels) == [1, 3]

    # Where a mask means nothing (an affine), a masked array is still refused.
    with pytest.raises(TypeError, match="a masked array"):
        stvd.distance(tensors(), SEED, affine=np.ma.masked_array(AFFINE), tensor_order="lower", tensor_kind="metric")


def gzip_member(data):
    compressor = zlib.compressobj(9, zlib.DEFLATED, 31)
    return compressor.compress(data) + compressor.flush()


@pytest.fixture(scope="module")
def huge_grid_image(tmp_path_factory):
    """800^3 voxels of zeros in half a megabyte: a header, then 500 gzip
    members of 1,024,000 zero bytes."""
    header = nib.Nifti1Header()
    header.set_data_shape((800, 800, 800))
    header.set_data_dtype(np.uint8)
    header.set_qform(np.eye(4), code=1)
    header.set_sform(np.eye(4), code=1)
    header["vox_offset"] = 352
    path = tmp_path_factory.mktemp("bomb") / "huge.nii.gz"
    zeros = gzip_member(bytes(1024000))
    with open(path, "wb") as bomb:
        bomb.write(gzip_member(header.binaryblock + b"\0" * 4))
        for _ in range(500):
            bomb.write(zeros)
    return path


@pytest.mark.parametrize("role", ["mask", "seed_labels", "labels", "target_labels"])
@pytest.mark.parametrize("given_as", ["path", "NiBabel image"])
def test_a_side_input_on_a_huge_grid_is_refused_from_its_header(huge_grid_image, role, given_as):
    image = huge_grid_image if given_as == "path" else nib.load(huge_grid_image)
    common = dict(affine=AFFINE, tensor_order="lower", tensor_kind="metric")
    start = time.process_time()
    with pytest.raises(ValueError) as caught:
        if role == "mask":
            stvd.distance(tensors(), SEED, mask=image, **common)
        elif role == "seed_labels":
            stvd.distance(tensors(), seed_labels=image, **common)
        elif role == "labels":
            stvd.connectivity(tensors(), image, threads=1, **common)
        else:
            stvd.trace_paths(stvd.propagate(tensors(), SEED, **common), target_labels=image)
    seconds = time.process_time() - start
    assert "on another grid than" in str(caught.value) and "(size 800x800x800 differs from 12x10x8)" in str(
        caught.value), caught.value
    assert seconds < 2, f"{seconds:.1f} s of CPU time"  # read in full: 3 GB, 15 to 50 s


def test_a_gzip_stream_is_read_only_as_far_as_its_header_needs(tmp_path):
    # Seed labels on the grid, followed by 4 GiB of zeros in 256 more gzip members.
    seeds = np.zeros(SHAPE, np.uint8)
    seeds[SEED] = 1
    nib.save(nib.Nifti1Image(seeds, AFFINE), tmp_path / "plain.nii")
    zeros = gzip_member(bytes(16 << 20))
    with open(tmp_path / "seeds.nii.gz", "wb") as out:
        out.write(gzip_member((tmp_path / "plain.nii").read_bytes()))
        for _ in range(256):
            out.write(zeros)
    start = time.process_time()
    result = stvd.distance(tensors(), seed_labels=tmp_path / "seeds.nii.gz", affine=AFFINE, tensor_order="lower",
                           tensor_kind="metric")
    seconds = time.process_time() - start
    np.testing.assert_array_equal(np.asanyarray(result.dataobj), distances())
    assert seconds < 2, f"{seconds:.1f} s of CPU time"  # counting the whole stream took 2.7 s per GiB
