"""Paths and connectivity through the Python API are the tool's: the same
points, the same per-path figures and the same matrices, from one
propagation that the calls share."""

import csv
import warnings

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import (CC_BODY, CC_BODY_L_LATERAL, CC_BODY_R_LATERAL, CST_L, CST_L_HIGH, CST_L_LOW, DIPY_5D, run_tool)


def read_tsv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f, delimiter="\t"))


def fixed(x, decimals=4):
    return "n/a" if not np.isfinite(x) else f"{x:.{decimals}f}"


@pytest.fixture(scope="module")
def target_labels(dipy_image, tmp_path_factory):
    labels = np.zeros(dipy_image.shape[:3], np.int16)
    labels[64:67, 51:54, 1:4] = 7  # around CST_L_low
    labels[42:45, 52:55, 2:5] = 9  # around CST_R_low
    path = tmp_path_factory.mktemp("labels") / "targets.nii.gz"
    nib.save(nib.Nifti1Image(labels, dipy_image.affine), path)
    return path


@pytest.fixture(scope="module")
def from_cc_body(dipy_image):
    return stvd.propagate(dipy_image, CC_BODY)


@pytest.mark.parametrize("tool_options, keywords", [
    ([], {}),
    (["--no-refine", "--step", "0.5", "--smooth", "2"], dict(refine=False, step=0.5, smooth=2)),
    (["--discrete"], dict(discrete=True)),
])
def test_paths_are_the_tools(tmp_path, from_cc_body, target_labels, tool_options, keywords):
    tck = tmp_path / "paths.tck"
    target_point = "-14.6,-4.8,87.7"  # CST_L_high in RAS
    run_tool("path", DIPY_5D, "--seed-voxel", "55,54,15", "--target-voxel", "62,54,18", "--target-voxel",
             "49,54,16", "--target-point", target_point, "--targets", target_labels, "-o", tck, "-q", *tool_options)
    table = read_tsv(tmp_path / "paths.tsv")
    tool_lines = list(nib.streamlines.load(str(tck)).streamlines)

    paths = stvd.trace_paths(from_cc_body, [CC_BODY_L_LATERAL, CC_BODY_R_LATERAL],
                             target_points=[(-14.6, -4.8, 87.7)], target_labels=target_labels, **keywords)
    assert len(paths) == len(table) == len(tool_lines) == 5
    for n, row in enumerate(table):
        assert paths.targets[n] == row["target"]
        assert tuple(paths.target_voxels[n]) == (int(row["target_i"]), int(row["target_j"]), int(row["target_k"]))
        assert tuple(paths.seed_voxels[n]) == (int(row["seed_i"]), int(row["seed_j"]), int(row["seed_k"]))
        for key in ("geodesic_mm", "euclidean_mm", "straight_mm", "metric_length_mm", "mean_fa"):
            assert fixed(getattr(paths, key)[n]) == row[key], key
        assert len(paths[n]) == int(row["points"])
        assert paths.gradient_steps[n] == int(row["gradient_steps"])
        assert paths.discrete_points[n] == int(row["discrete_points"])
        fallbacks = ",".join(f"{k}={v}" for k, v in paths.fallbacks[n].items()) or "none"
        assert fallbacks == row["fallbacks"]
        assert paths.refine_iterations[n] == int(row["refine_iterations"])
        # .tck holds single-precision RAS millimetres.
        assert paths[n].shape == tool_lines[n].shape
        assert np.allclose(paths[n], tool_lines[n], rtol=0, atol=2e-5)
        assert len(paths.fa[n]) == len(paths[n])
    # Paths run from the seed (first point) to the target (last point).
    seed_ras = nib.affines.apply_affine(from_cc_body.affine, CC_BODY)
    assert np.allclose(paths[0][0], seed_ras) and np.allclose(paths[0][-1],
                                                              nib.affines.apply_affine(from_cc_body.affine,
                                                                                       CC_BODY_L_LATERAL))
    # The geodesic length is the distance value at the target.
    assert paths.geodesic_mm[0] == from_cc_body.distance[CC_BODY_L_LATERAL]


def test_a_tractogram_saves_as_trk_and_tck_with_the_figures(tmp_path, from_cc_body):
    paths = stvd.trace_paths(from_cc_body, [CC_BODY_L_LATERAL, CC_BODY_R_LATERAL, CST_L])
    tractogram = stvd.tractogram(paths)
    for name, header in (("paths.trk", paths.trk_header()), ("paths.tck", None)):
        with warnings.catch_warnings():  # NiBabel's .tck keeps no per-path values, and says so
            warnings.simplefilter("ignore", nib.streamlines.tck.DataWarning)
            nib.streamlines.save(tractogram, str(tmp_path / name), header=header)
        loaded = nib.streamlines.load(str(tmp_path / name))
        assert len(loaded.streamlines) == 3
        for ours, saved in zip(paths, loaded.streamlines):
            assert np.allclose(ours, saved, rtol=0, atol=2e-5)
    trk = nib.streamlines.load(str(tmp_path / "paths.trk"))
    assert np.allclose(trk.header["voxel_to_rasmm"], from_cc_body.affine, atol=1e-5)
    assert trk.header["voxel_order"] == b"LAS"
    assert np.allclose(trk.tractogram.data_per_streamline["geodesic_mm"][:, 0], paths.geodesic_mm)
    assert np.allclose(trk.tractogram.data_per_streamline["mean_fa"][:, 0], paths.mean_fa)
    assert np.allclose(np.concatenate(trk.tractogram.data_per_point["fa"][:, 0]), np.concatenate(paths.fa))


def test_paths_along_the_corpus_callosum_and_the_corticospinal_tract(dipy_image):
    """The geodesics of docs/paths.md: across the midline through the body of
    the corpus callosum, and up the corticospinal tract."""
    across = stvd.trace_paths(stvd.propagate(dipy_image, CC_BODY_R_LATERAL), CC_BODY_L_LATERAL)
    index = nib.affines.apply_affine(np.linalg.inv(across.affine), across[0])
    crossing = index[np.argmin(np.abs(index[:, 0] - 55))]
    assert np.linalg.norm(crossing - CC_BODY) < 1.0
    assert across.mean_fa[0] > 0.75
    up = stvd.trace_paths(stvd.propagate(dipy_image, CST_L_LOW), CST_L_HIGH)
    steps = np.abs(np.diff(up[0], axis=0))
    assert steps[:, 2].sum() > 0.9 * np.linalg.norm(np.diff(up[0], axis=0), axis=1).sum()


@pytest.fixture(scope="module")
def regions(dipy_image, tmp_path_factory):
    labels = np.zeros(dipy_image.shape[:3], np.uint8)
    for value, (i, j, k) in enumerate([CC_BODY, CST_L, (41, 51, 12), CC_BODY_L_LATERAL], start=1):
        labels[i - 1:i + 2, j - 1:j + 2, k - 1:k + 2] = value
    labels[0:2, 0:2, 0:2] = 5  # outside the brain: left out
    path = tmp_path_factory.mktemp("regions") / "regions.nii.gz"
    nib.save(nib.Nifti1Image(labels, dipy_image.affine), path)
    return labels, path


def test_connectivity_is_the_tools_for_any_number_of_threads(tmp_path, dipy_image, regions, from_cc_body):
    labels, path = regions
    run_tool("connectivity", DIPY_5D, "--labels", path, "-o", tmp_path / "table.tsv", "-q")
    table = read_tsv(tmp_path / "table.tsv")
    for threads in (1, 2):
        c = stvd.connectivity(dipy_image, labels, threads=threads)
        assert list(c.labels) == [1, 2, 3, 4]
        assert c.labels_left_out == 1
        assert c.threads == threads
        assert list(c.voxels) == [27, 27, 27, 27]
        assert np.all(np.isnan(np.diag(c.geodesic_mm)))
        for row in table:
            a, b = list(c.labels).index(int(row["region_a"])), list(c.labels).index(int(row["region_b"]))
            assert fixed(c.geodesic_mm[a, b]) == row["geodesic_mm"]
            assert fixed(c.path_mm[a, b]) == row["path_mm"]
            assert fixed(c.straight_mm[a, b]) == row["straight_mm"]
            assert fixed(c.connectivity[a, b]) == row["connectivity"]
    # From a propagation: its field and method, the same matrices.
    again = stvd.connectivity(from_cc_body, path)
    assert np.array_equal(again.geodesic_mm, c.geodesic_mm, equal_nan=True)
