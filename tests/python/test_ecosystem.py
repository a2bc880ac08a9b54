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


# --- results pickle (item 8)

def round_trip(value):
    return pickle.loads(pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL))


def test_a_propagation_pickles_and_keeps_everything(dipy_image):
    result = stvd.propagate(dipy_image, CC_BODY, mask=str(MASK))
    back = round_trip(result)
    assert isinstance(back, stvd.Propagation)
    for name in ("distance", "predecessor", "seeds", "in_domain", "fractional_anisotropy", "affine"):
        assert np.array_equal(getattr(back, name), getattr(result, name)), name
    for name in ("termination", "finalized_vertices", "relaxed_edges", "peak_state_bytes", "method", "k",
                 "chain_measure", "stencil", "domain_connectivity", "shape", "zooms", "voxel_counts",
                 "tensor_info", "input_files", "label_seeds_left_out"):
        assert getattr(back, name) == getattr(result, name), name
    # The distance map is the same image, and paths and connectivity work
    # from the copy as from the original, with the same numbers.
    assert np.array_equal(back.distance_map().affine, result.distance_map().affine)
    assert np.array_equal(np.asanyarray(back.distance_map().dataobj), np.asanyarray(result.distance_map().dataobj))
    targets = [CC_BODY_L_LATERAL, CC_BODY_R_LATERAL, CST_L]
    original, copied = stvd.trace_paths(result, targets), stvd.trace_paths(back, targets)
    assert all(np.array_equal(a, b) for a, b in zip(original, copied))
    assert np.array_equal(original.mean_fa, copied.mean_fa)
    regions = np.zeros(dipy_image.shape[:3], np.uint8)
    regions[54:57, 53:56, 14:17], regions[67:70, 49:52, 10:13] = 1, 2
    assert np.array_equal(stvd.connectivity(back, regions).geodesic_mm,
                          stvd.connectivity(result, regions).geodesic_mm, equal_nan=True)


def test_a_propagation_accepted_in_a_wrong_frame_pickles_with_its_frame_check():
    # The copy builds its metric again: it must not stop at the frame check
    # the original was told to accept, and keeps what a QC page states.
    result = stvd.propagate(str(DIPY_5D), CC_BODY, tensor_frame="world", accept_misaligned_tensors=True,
                            max_distance=5)
    assert result.tensor_info["frame_check"]["verdict"] == "mismatch"
    back = round_trip(result)
    assert back.tensor_info == result.tensor_info
    assert np.array_equal(back.distance, result.distance)


def test_paths_and_connectivity_pickle(tmp_path):
    result = small_propagation()
    paths = stvd.trace_paths(result, [(7, 6, 5), (0, 7, 6)])
    back = round_trip(paths)
    assert isinstance(back, stvd.Paths) and len(back) == 2
    assert all(np.array_equal(a, b) for a, b in zip(back, paths))
    for name in ("geodesic_mm", "euclidean_mm", "straight_mm", "target_voxels", "seed_voxels", "affine"):
        assert np.array_equal(getattr(back, name), getattr(paths, name), equal_nan=True), name
    assert back.targets == paths.targets and back.shape == paths.shape
    # A copy still saves as the original does, byte for byte.
    paths.save(tmp_path / "a.tck")
    back.save(tmp_path / "b.tck")
    assert (tmp_path / "a.tck").read_bytes() == (tmp_path / "b.tck").read_bytes()
    regions = np.zeros(SHAPE, np.uint8)
    regions[0:2, 0:2, 0:2], regions[6:8, 5:7, 4:6] = 1, 2
    c = stvd.connectivity(result, regions)
    c_back = round_trip(c)
    assert isinstance(c_back, stvd.Connectivity)
    assert np.array_equal(c_back.geodesic_mm, c.geodesic_mm, equal_nan=True)
    assert np.array_equal(c_back.labels, c.labels)


def _distance_at(result, voxel):
    return float(result.distance[voxel])


def test_a_propagation_goes_through_a_process_pool():
    # A child process gets a pickled Propagation and reads it; a spawned one,
    # as Dask's and multiprocessing's defaults on macOS and Windows do.
    result = small_propagation()
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        assert pool.apply(_distance_at, (result, (7, 6, 5))) == result.distance[7, 6, 5]
        back = pool.apply(round_trip, (result,))
    assert np.array_equal(back.distance, result.distance)


def test_a_damaged_state_is_refused():
    result = small_propagation()
    state = result._result.__getstate__()
    with pytest.raises(ValueError, match="unpickling stvd"):
        type(result._result).__new__(type(result._result)).__setstate__(state[:3])


# --- paths merge (item 9)

def test_paths_of_several_runs_merge_into_paths_nibabel_saves(tmp_path):
    first = stvd.trace_paths(small_propagation(), [(7, 6, 5), (0, 7, 6)])
    second = stvd.trace_paths(stvd.propagate(small_tensors(), (6, 1, 1), affine=AFFINE, tensor_order="lower",
                                             tensor_kind="metric"), [(1, 6, 6)])
    merged = first + second
    assert isinstance(merged, stvd.Paths) and len(merged) == 3
    assert all(np.array_equal(a, b) for a, b in zip(merged, list(first) + list(second)))
    assert np.array_equal(merged.geodesic_mm, np.concatenate([first.geodesic_mm, second.geodesic_mm]))
    assert np.array_equal(merged.seed_voxels, [(2, 2, 2), (2, 2, 2), (6, 1, 1)])
    assert merged.targets == first.targets + second.targets
    assert np.array_equal(merged.affine, first.affine) and merged.shape == first.shape
    assert len(first) == 2  # the operands are left as they were
    assert len(stvd.Paths.merge([first, second, first])) == 5
    # NiBabel saves the merged set; stvd saves it as the tool would.
    nib.streamlines.save(stvd.tractogram(merged), str(tmp_path / "merged.trk"), header=merged.trk_header())
    loaded = nib.streamlines.load(str(tmp_path / "merged.trk"))
    assert len(loaded.streamlines) == 3
    assert np.allclose(loaded.tractogram.data_per_streamline["geodesic_mm"][:, 0], merged.geodesic_mm, rtol=1e-6)
    merged.save(tmp_path / "merged.tck")
    assert len(nib.streamlines.load(str(tmp_path / "merged.tck")).streamlines) == 3
    # += gives Paths as well, and a slice keeps the figures of its paths.
    grown = first
    grown += second
    assert isinstance(grown, stvd.Paths) and len(grown) == 3 and len(first) == 2
    tail = merged[1:]
    assert isinstance(tail, stvd.Paths) and np.array_equal(tail.geodesic_mm, merged.geodesic_mm[1:])
    assert isinstance(merged[0], np.ndarray)


def test_paths_on_another_grid_do_not_merge():
    first = stvd.trace_paths(small_propagation(), [(7, 6, 5)])
    moved = AFFINE.copy()
    moved[0, 3] += 1.0
    other = stvd.trace_paths(stvd.propagate(small_tensors(), (2, 2, 2), affine=moved, tensor_order="lower",
                                            tensor_kind="metric"), [(7, 6, 5)])
    with pytest.raises(ValueError, match="paths on another grid"):
        first + other
    with pytest.raises(TypeError, match="stvd.Paths"):
        stvd.tractogram(list(first) + list(other))
    with pytest.raises(TypeError):
        first + [np.zeros((2, 3))]


# --- write_report takes affine= like every other call (item 11)

def test_a_connectivity_page_from_arrays_takes_the_affine(tmp_path, dipy_image, dipy_components):
    from stvd.report import write_report

    regions = np.zeros(dipy_image.shape[:3], np.uint8)
    regions[54:57, 53:56, 14:17], regions[67:70, 49:52, 10:13] = 1, 2
    c = stvd.connectivity(dipy_components, regions, affine=dipy_image.affine, tensor_order="lower", threads=1)
    summary = write_report(tmp_path / "c.html", connectivity=c, labels=regions, tensors=dipy_components,
                           affine=dipy_image.affine, tensor_order="lower")
    assert (tmp_path / "c.html").is_file() and summary is not None
    # The same page from the image; an affine that is not the result's is refused.
    write_report(tmp_path / "i.html", connectivity=c, labels=regions, tensors=dipy_image)
    result = stvd.propagate(dipy_components, CC_BODY, affine=dipy_image.affine, tensor_order="lower",
                            max_distance=5)
    write_report(tmp_path / "r.html", result, tensors=dipy_components, affine=dipy_image.affine)
    with pytest.raises(ValueError, match="affine"):
        write_report(tmp_path / "x.html", result, affine=np.eye(4))
    assert not (tmp_path / "x.html").exists()


# --- seeds as float world millimetres, as DIPY gives them (item 13)

def test_dipy_seeds_in_world_millimetres_go_to_seed_points(dipy_image):
    from dipy.tracking.utils import seeds_from_mask

    region = np.zeros(dipy_image.shape[:3], bool)
    region[54:57, 53:55, 15] = True
    points = seeds_from_mask(region, dipy_image.affine, density=1)  # float64 RAS+ millimetres, voxel centres
    assert points.dtype.kind == "f" and len(points) == 6
    by_points = stvd.propagate(dipy_image, seed_points=points)
    by_voxels = stvd.propagate(dipy_image, np.argwhere(region))
    assert sorted(map(tuple, by_points.seeds)) == sorted(map(tuple, np.argwhere(region)))
    assert np.array_equal(by_points.distance, by_voxels.distance)
    # Targets in world millimetres, as nibabel.streamlines gives points.
    target = nib.affines.apply_affine(dipy_image.affine, CC_BODY_L_LATERAL)
    paths = stvd.trace_paths(by_points, target_points=[target])
    assert tuple(paths.target_voxels[0]) == CC_BODY_L_LATERAL
    assert np.allclose(paths[0][-1], target, atol=1e-3)  # the path ends at the target, in the same frame


def test_float_seeds_given_as_voxels_are_refused_with_a_pointer_to_seed_points(dipy_image):
    # Whole numbers as floats are still not taken for indices: DIPY's seeds
    # are world millimetres, and a point that happens to be whole is one too.
    for seeds in ((55.0, 54.0, 15.0), np.array([[55, 54, 15]], np.float32), [(6.4, 11.6, 76.3)]):
        with pytest.raises(TypeError) as caught:
            stvd.propagate(dipy_image, seeds)
        assert "seed_points=" in str(caught.value) and "RAS+" in str(caught.value), caught.value
    result = stvd.propagate(dipy_image, CC_BODY, max_distance=5)
    with pytest.raises(TypeError, match="target_points="):
        stvd.trace_paths(result, [(55.0, 54.0, 16.0)])


# --- one message for one bad file, however it is run (item 12)

def test_a_corrupt_file_gives_the_same_message_through_the_cohort_nipype_and_the_calls(tmp_path, dipy_image):
    import csv

    import stvd.cohort
    from stvd.interfaces import Distance

    whole = DIPY_5D.read_bytes()
    (tmp_path / "cut.nii.gz").write_bytes(whole[:len(whole) // 2])
    (tmp_path / "good.nii.gz").write_bytes(whole)
    labels = np.zeros(dipy_image.shape[:3], np.uint8)
    labels[54:57, 53:56, 14:17] = 1
    nib.save(nib.Nifti1Image(labels, dipy_image.affine), tmp_path / "labels.nii.gz")
    label_bytes = (tmp_path / "labels.nii.gz").read_bytes()
    (tmp_path / "cut_labels.nii.gz").write_bytes(label_bytes[:len(label_bytes) // 2])
    (tmp_path / "m.tsv").write_text("subject\ttensors\tlabels\tseeds\n"
                                    "tensors_cut\tcut.nii.gz\tlabels.nii.gz\tlabels.nii.gz\n"
                                    "seeds_cut\tgood.nii.gz\tlabels.nii.gz\tcut_labels.nii.gz\n")
    cohort = stvd.cohort.run(tmp_path / "m.tsv", tmp_path / "out", serial=True, report=False, connectivity=False)
    assert sorted(cohort.failed) == ["seeds_cut", "tensors_cut"]
    with open(tmp_path / "out" / "cohort.tsv", newline="") as table:
        through_cohort = {row["subject"]: row["error"] for row in csv.DictReader(table, delimiter="\t")}

    def message(call):
        with pytest.raises(ValueError) as caught:
            call()
        return str(caught.value)

    cut, cut_labels = str(tmp_path / "cut.nii.gz"), str(tmp_path / "cut_labels.nii.gz")
    by_call = {"tensors_cut": message(lambda: stvd.propagate(cut, CC_BODY)),
               "seeds_cut": message(lambda: stvd.propagate(str(tmp_path / "good.nii.gz"), seed_labels=cut_labels))}
    by_nipype = {
        "tensors_cut": message(lambda: Distance(in_file=cut, seed_voxels=[CC_BODY],
                                                out_file=str(tmp_path / "a.nii.gz")).run()),
        "seeds_cut": message(lambda: Distance(in_file=str(tmp_path / "good.nii.gz"), seed_file=cut_labels,
                                              out_file=str(tmp_path / "b.nii.gz")).run())}
    assert by_call["tensors_cut"] == f"{cut}: the compressed data are damaged or cut short"
    for subject in by_call:
        assert through_cohort[subject] == by_call[subject] == by_nipype[subject], subject


# --- connectivity with region names, as pandas tables, one missing value (item 10)

def test_connectivity_has_names_pandas_tables_and_the_tools_missing_value(tmp_path):
    import csv

    from conftest import run_tool

    pandas = pytest.importorskip("pandas")  # python3-pandas, installed by scripts/setup.sh
    # Two halves of the small grid, a wall of masked voxels between them:
    # regions 3 and 5 are connected, 9 is not connected to either.
    mask = np.ones(SHAPE, np.uint8)
    mask[4, :, :] = 0
    labels = np.zeros(SHAPE, np.int16)
    labels[0:2, 0:2, 0:2], labels[2:4, 5:7, 4:6], labels[6:8, 5:7, 4:6] = 3, 5, 9
    header = nib.Nifti1Header()
    header.set_intent("symmetric matrix")
    nib.save(nib.Nifti1Image(small_tensors()[:, :, :, np.newaxis, :], AFFINE, header), tmp_path / "t.nii.gz")
    nib.save(nib.Nifti1Image(mask, AFFINE), tmp_path / "mask.nii.gz")
    nib.save(nib.Nifti1Image(labels, AFFINE), tmp_path / "labels.nii.gz")
    (tmp_path / "dseg.tsv").write_text("index\tname\n3\tleft_thing\n5\tright_thing\n9\tfar_away\n")
    (tmp_path / "LUT.txt").write_text("#No. Label Name:   R   G   B   A\n\n3  left_thing  70 130 180 0\n"
                                      "5  right_thing 245 245 245 0\n")

    c = stvd.connectivity(str(tmp_path / "t.nii.gz"), str(tmp_path / "labels.nii.gz"), mask=str(tmp_path / "mask.nii.gz"),
                          tensor_kind="metric", threads=1, label_names=tmp_path / "dseg.tsv")
    assert c.names == ["left_thing", "right_thing", "far_away"]
    lut = stvd.connectivity(str(tmp_path / "t.nii.gz"), str(tmp_path / "labels.nii.gz"),
                            mask=str(tmp_path / "mask.nii.gz"), tensor_kind="metric", threads=1,
                            label_names=tmp_path / "LUT.txt")
    assert lut.names == ["left_thing", "right_thing", "9"]  # a label the lookup does not name keeps its value
    assert stvd.read_label_names({3: "a", "5": "b"}) == {3: "a", 5: "b"}

    # One missing value: NaN on the diagonal and for pairs not connected, in
    # every measure; the tool writes n/a in its table and nan in its matrices.
    missing = np.eye(3, dtype=bool)
    missing[0:2, 2] = missing[2, 0:2] = True
    for measure in ("geodesic_mm", "path_mm", "straight_mm", "connectivity"):
        assert np.array_equal(np.isnan(getattr(c, measure)), missing), measure
    run_tool("connectivity", tmp_path / "t.nii.gz", "--labels", tmp_path / "labels.nii.gz", "--mask",
             tmp_path / "mask.nii.gz", "--tensor-kind", "metric", "--threads", "1", "-o", tmp_path / "c.tsv",
             "--matrix", tmp_path / "d.csv", "--matrix-index", tmp_path / "ci.csv", "-q")
    for file, measure in (("d.csv", "geodesic_mm"), ("ci.csv", "connectivity")):
        matrix = np.loadtxt(tmp_path / file, delimiter=",")
        assert np.array_equal(np.isnan(matrix), missing), file
        assert np.allclose(matrix[~missing], getattr(c, measure)[~missing], rtol=1e-4), file

    # pandas: the long table is the tool's table with names; the square one
    # is the matrix by name.
    tool_table = pandas.read_csv(tmp_path / "c.tsv", sep="\t")
    long = c.to_dataframe()
    assert list(long.columns) == ["region_a", "region_b", "name_a", "name_b", "geodesic_mm", "path_mm",
                                  "straight_mm", "connectivity", "voxels_a", "voxels_b"]
    assert len(long) == len(tool_table) == 6
    assert list(long.region_a) == list(tool_table.region_a) and list(long.region_b) == list(tool_table.region_b)
    for measure in ("geodesic_mm", "path_mm", "straight_mm", "connectivity"):
        assert np.array_equal(long[measure].isna(), tool_table[measure].isna()), measure
        assert np.allclose(long[measure].dropna(), tool_table[measure].dropna(), atol=1e-4), measure
    square = c.to_dataframe("square", measure="geodesic_mm")
    assert list(square.index) == list(square.columns) == c.names
    assert square.loc["left_thing", "right_thing"] == c.geodesic_mm[0, 1]
    assert np.isnan(square.loc["left_thing", "left_thing"]) and np.isnan(square.loc["left_thing", "far_away"])
    with open(tmp_path / "c.tsv", newline="") as table:
        assert sum(row["geodesic_mm"] == "n/a" for row in csv.DictReader(table, delimiter="\t")) == 4
