"""A synthetic cohort made from the shipped brain, deterministically: the
cohort tests and bench/cohort.py build it instead of checking in subjects.

Subjects:
- ``base``: the shipped tensors and mask as they are;
- ``flipped``: the same brain stored with its first axis reversed (data,
  mask, labels and seeds reversed, the affine's first column negated and
  its origin moved, the voxel-frame components xy and xz negated): the same
  physical brain under another header, so its geodesic distances between
  the same regions must agree with ``base``'s;
- ``s02`` ... : the brain under a small smooth deformation (about a voxel),
  with noise on every tensor (T -> A T A^T, A = I + 0.02 S, S a symmetric
  Gaussian matrix per voxel, which keeps them positive definite);
- ``corrupt``: a tensor file cut in half;
- ``seed_outside``: a seed set whose voxel lies outside the brain mask.

Each subject has a label image of four 3x3x3 regions (corpus callosum body
and genu, left and right corticospinal tract, from seeds.tsv) and a seeds
table of two seed sets (``CC_body``, ``CST_L``). ``crop`` keeps a box around
them (the tests use it to stay fast).

    python3 tests/python/synthetic_cohort.py OUTDIR [--subjects N] [--crop]
"""

import argparse
import os
import pathlib

import nibabel as nib
import numpy as np

SAMPLE = pathlib.Path(os.environ.get("STVD_SAMPLE_DATA_DIR", pathlib.Path(__file__).resolve().parents[2]
                                     / "sample_data" / "dti_philips_biobank"))
REGIONS = {1: (55, 54, 15), 2: (55, 75, 9), 3: (68, 50, 11), 4: (41, 51, 12)}  # CC_body, CC_genu, CST_L, CST_R
SEED_SETS = {"CC_body": [(55, 54, 15)], "CST_L": [(68, 50, 11), (68, 50, 12)]}
CROP = (slice(36, 76), slice(36, 82), slice(4, 24))  # 40 x 46 x 20 voxels around the regions
# The order of the shipped 5D file's six components (NIfTI SYMMATRIX: xx, xy, yy, xz, yz, zz).
XY, XZ = 1, 3


def _cropped(image, box):
    data = np.asanyarray(image.dataobj)[box]
    offset = np.array([s.start for s in box] + [1.0])
    affine = image.affine.copy()
    affine[:, 3] = image.affine @ offset
    return data, affine


def _save(data, affine, header, path):
    out = header.copy()
    out.set_data_dtype(data.dtype)
    nib.save(nib.Nifti1Image(data, affine, out), path)


def _labels(shape, shift):
    labels = np.zeros(shape, np.uint8)
    for value, voxel in REGIONS.items():
        i, j, k = (c - s for c, s in zip(voxel, shift))
        labels[i - 1:i + 2, j - 1:j + 2, k - 1:k + 2] = value
    return labels


def _seeds_table(path, sets, shift, flip_size=None):
    lines = ["name\ti\tj\tk"]
    for name, voxels in sets.items():
        for voxel in voxels:
            i, j, k = (c - s for c, s in zip(voxel, shift))
            if flip_size is not None:
                i = flip_size - 1 - i
            lines.append(f"{name}\t{i}\t{j}\t{k}")
    path.write_text("\n".join(lines) + "\n")


def _deformed(tensors, mask, rng):
    """The tensors and mask under a smooth displacement of about a voxel,
    with multiplicative noise on each tensor."""
    from scipy import ndimage

    shape = mask.shape
    grid = np.meshgrid(*(np.arange(n, dtype=np.float64) for n in shape), indexing="ij")
    coordinates = []
    for axis in range(3):
        phase = rng.uniform(0, 2 * np.pi, 3)
        amplitude = rng.uniform(0.5, 1.0)
        wave = np.ones(shape)
        for a in range(3):
            wave = wave * np.sin(2 * np.pi * grid[a] / shape[a] + phase[a])
        coordinates.append(grid[axis] + amplitude * wave)
    warped = np.stack([ndimage.map_coordinates(tensors[..., c], coordinates, order=1, mode="nearest")
                       for c in range(6)], axis=-1)
    warped_mask = ndimage.map_coordinates(mask, coordinates, order=0, mode="nearest")
    # Noise: A T A^T with A = I + 0.02 S.
    lower = [(0, 0), (0, 1), (1, 1), (0, 2), (1, 2), (2, 2)]
    matrices = np.zeros(shape + (3, 3))
    for c, (a, b) in enumerate(lower):
        matrices[..., a, b] = matrices[..., b, a] = warped[..., c]
    noise = rng.normal(size=shape + (3, 3))
    a = np.eye(3) + 0.02 * (noise + np.swapaxes(noise, -1, -2)) / 2
    noisy = a @ matrices @ np.swapaxes(a, -1, -2)
    return np.stack([noisy[..., a, b] for a, b in lower], axis=-1).astype(np.float32), warped_mask


def make_cohort(folder, subjects=16, crop=False, seed=18):
    """Writes the cohort into ``folder`` (created) with ``subjects`` subjects
    in all (at least 4: base, flipped, corrupt, seed_outside, then deformed
    ones); returns the manifest's path. The same arguments give the same
    files."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    image = nib.load(SAMPLE / "dti_tensor_dipy5d.nii.gz")
    mask_image = nib.load(SAMPLE / "dti_mask.nii.gz")
    box = CROP if crop else tuple(slice(0, n) for n in image.shape[:3])
    shift = [s.start for s in box]
    tensors, affine = _cropped(image, box)           # (X, Y, Z, 1, 6)
    mask, _ = _cropped(mask_image, box)
    mask = mask.astype(np.uint8)
    labels = _labels(mask.shape, shift)
    rows = ["subject\ttensors\tlabels\tmask\tseeds"]

    def add(name, tensor_data, tensor_affine, mask_data, label_data, seed_sets=SEED_SETS, flip_size=None):
        d = folder / name
        d.mkdir(exist_ok=True)
        _save(tensor_data, tensor_affine, image.header, d / "tensors.nii.gz")
        _save(mask_data, tensor_affine, mask_image.header, d / "mask.nii.gz")
        _save(label_data, tensor_affine, mask_image.header, d / "labels.nii.gz")
        _seeds_table(d / "seeds.tsv", seed_sets, shift, flip_size)
        rows.append(f"{name}\t{name}/tensors.nii.gz\t{name}/labels.nii.gz\t{name}/mask.nii.gz\t{name}/seeds.tsv")

    add("base", tensors, affine, mask, labels)
    # The first axis reversed: voxel i holds what voxel n-1-i held, and the
    # affine maps it to the same point; in the voxel frame the components
    # with one x index change sign.
    n = mask.shape[0]
    flip = np.diag([-1.0, 1.0, 1.0, 1.0])
    flip[0, 3] = n - 1
    flipped = tensors[::-1].copy()
    flipped[..., XY] *= -1
    flipped[..., XZ] *= -1
    add("flipped", flipped, affine @ flip, mask[::-1].copy(), labels[::-1].copy(), flip_size=n)
    outside = tuple(int(c) + s for c, s in zip(np.argwhere(mask == 0)[0], shift))  # in the image, not the brain
    add("seed_outside", tensors, affine, mask, labels,
        seed_sets={"CC_body": SEED_SETS["CC_body"], "outside": [outside]})
    for index in range(2, subjects - 2):
        deformed, deformed_mask = _deformed(tensors[:, :, :, 0, :], mask, rng)
        add(f"s{index:02d}", deformed[:, :, :, np.newaxis, :], affine, deformed_mask, labels)
    add("corrupt", tensors, affine, mask, labels)
    whole = (folder / "corrupt" / "tensors.nii.gz").read_bytes()
    (folder / "corrupt" / "tensors.nii.gz").write_bytes(whole[:len(whole) // 2])
    manifest = folder / "manifest.tsv"
    manifest.write_text("\n".join(rows) + "\n")
    return manifest


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder")
    parser.add_argument("--subjects", type=int, default=16)
    parser.add_argument("--crop", action="store_true", help="a box around the regions, not the whole brain")
    arguments = parser.parse_args()
    print(make_cohort(arguments.folder, arguments.subjects, arguments.crop))
