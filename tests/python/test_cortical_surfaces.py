"""Cortical surface files (docs/surfaces.md, "Cortical surfaces"): NiBabel
writes FreeSurfer and GIfTI surfaces, annotations, labels and per-vertex
files; the tool and the package read them, compute distances from a region
and write GIfTI shape/func and FreeSurfer curv files, which NiBabel reads
back. The reference distances are the package's on the arrays NiBabel read,
seeded with the vertices NiBabel says the region has."""

import json
import shutil
import subprocess

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import run_tool, tool_message


def icosphere(order, radius):
    """An icosphere: the icosahedron's faces split into 4, `order` times,
    its vertices pushed onto the sphere (order 3: 642 vertices)."""
    t = (1.0 + 5.0 ** 0.5) / 2.0
    vertices = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
                (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
             (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    vertices = [np.array(v, float) / np.linalg.norm(v) for v in vertices]
    for _ in range(order):
        middle = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                m = vertices[a] + vertices[b]
                vertices.append(m / np.linalg.norm(m))
                middle[key] = len(vertices) - 1
            return middle[key]

        split = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = split
    return np.array(vertices) * radius, np.array(faces, dtype=np.int32)


# A "cortex" of radius 40 mm, off-centre, and three regions by height.
COORDS, FACES = icosphere(3, 40.0)
COORDS = (COORDS + (3.0, -7.5, 12.0)).astype(np.float32)
N = len(COORDS)
HEIGHT = COORDS[:, 2] - 12.0
REGION = np.where(HEIGHT > 25.0, 1, np.where(HEIGHT < -25.0, 2, 0)).astype(np.int32)
NAMES = [b"unknown", b"precentral", b"lingual"]
CTAB = np.array([[25, 5, 25, 0, 0], [60, 20, 220, 0, 0], [225, 140, 140, 0, 0]], dtype=np.int32)
C_RAS = (1.5, -20.25, 8.0)
CONFORMED = {"head": np.array([2, 0, 20], dtype=np.int32), "valid": "1  # volume info valid",
             "filename": "orig.mgz", "volume": np.array([256, 256, 256]),
             "voxelsize": np.array([1.0, 1.0, 1.0]), "xras": np.array([-1.0, 0.0, 0.0]),
             "yras": np.array([0.0, 0.0, -1.0]), "zras": np.array([0.0, 1.0, 0.0]), "cras": np.array(C_RAS)}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cortical")
    f = {"folder": folder}
    f["pial"] = folder / "lh.pial"
    nib.freesurfer.write_geometry(str(f["pial"]), COORDS, FACES, volume_info=CONFORMED)
    f["annot"] = folder / "lh.aparc.annot"
    nib.freesurfer.write_annot(str(f["annot"]), REGION, CTAB, NAMES, fill_ctab=True)
    f["label"] = folder / "lh.precentral.label"
    rows = [f"{v} {COORDS[v][0]:.3f} {COORDS[v][1]:.3f} {COORDS[v][2]:.3f} 0.0" for v in np.flatnonzero(REGION == 1)]
    f["label"].write_text("#!ascii label  , from subject  vox2ras=TkReg\n" + f"{len(rows)}\n" + "\n".join(rows) + "\n")
    for encoding in ("GIFTI_ENCODING_B64GZ", "GIFTI_ENCODING_B64BIN", "GIFTI_ENCODING_ASCII"):
        image = nib.gifti.GiftiImage()
        image.add_gifti_data_array(nib.gifti.GiftiDataArray(
            COORDS, intent="NIFTI_INTENT_POINTSET", datatype="NIFTI_TYPE_FLOAT32", encoding=encoding,
            meta={"AnatomicalStructurePrimary": "CortexLeft"},
            coordsys=nib.gifti.GiftiCoordSystem(3, 3, np.eye(4))))
        image.add_gifti_data_array(nib.gifti.GiftiDataArray(
            FACES, intent="NIFTI_INTENT_TRIANGLE", datatype="NIFTI_TYPE_INT32", encoding=encoding))
        f[encoding] = folder / f"lh.{encoding[15:].lower()}.surf.gii"
        nib.save(image, f[encoding])
    labels = nib.gifti.GiftiImage()
    for key, name in enumerate(["???", "precentral", "lingual"]):
        label = nib.gifti.GiftiLabel(key=key, red=0.5, green=0.5, blue=0.5, alpha=1.0)
        label.label = name
        labels.labeltable.labels.append(label)
    labels.add_gifti_data_array(nib.gifti.GiftiDataArray(REGION, intent="NIFTI_INTENT_LABEL",
                                                         datatype="NIFTI_TYPE_INT32"))
    f["label_gii"] = folder / "lh.aparc.label.gii"
    nib.save(labels, f["label_gii"])
    return f


def region_seeds(name):
    """The region's vertices as NiBabel reads the annotation."""
    labels, _, names = nib.freesurfer.read_annot(FILES["annot"])
    return np.flatnonzero(labels == names.index(name.encode()))


FILES = {}


@pytest.fixture(scope="module", autouse=True)
def _remember(files):
    FILES.update(files)


def reference(seeds, surface=None, **options):
    """The package's distances on NiBabel's reading of the surface (the
    FreeSurfer one unless `surface` names a GIfTI file)."""
    if surface is None:
        coords, faces = nib.freesurfer.read_geometry(FILES["pial"])
    else:
        coords, faces = nib.load(surface).agg_data(("pointset", "triangle"))
    return stvd.surface_distance(coords.astype(np.float64), faces, seeds, **options)


def test_freesurfer_surface_and_annotation_to_gifti_and_curv(files, tmp_path):
    expected = reference(region_seeds("precentral"))
    assert np.all(np.isfinite(expected)) and expected.max() > 50.0
    shape, curv, stats = tmp_path / "lh.distance.shape.gii", tmp_path / "lh.distance", tmp_path / "run.json"
    for output in (shape, curv):
        run_tool("distance", files["pial"], "--seeds", files["annot"], "--seed-region", "precentral", "-o", output,
                 "--stats", stats, "-q")
    gifti = nib.load(shape)
    assert len(gifti.darrays) == 1 and gifti.darrays[0].intent == nib.nifti1.intent_codes["NIFTI_INTENT_SHAPE"]
    assert gifti.meta["AnatomicalStructurePrimary"] == "CortexLeft"
    np.testing.assert_array_equal(gifti.darrays[0].data, expected.astype(np.float32))
    # Compressed, as NiBabel and Connectome Workbench write GIfTI data.
    assert gifti.darrays[0].encoding == nib.gifti.gifti.gifti_encoding_codes.code["GIFTI_ENCODING_B64GZ"]
    np.testing.assert_array_equal(nib.freesurfer.read_morph_data(curv), expected.astype(np.float32))
    run = json.loads(stats.read_text())
    assert run["mesh"]["coordinate_space"] == "tkr-RAS" and run["mesh"]["transformed_space"] == "scanner RAS"
    # A conformed volume: scanner RAS = tkr-RAS + c_ras.
    np.testing.assert_allclose(np.reshape(run["mesh"]["transform"], (4, 4)),
                               [[1, 0, 0, C_RAS[0]], [0, 1, 0, C_RAS[1]], [0, 0, 1, C_RAS[2]], [0, 0, 0, 1]],
                               atol=1e-9)
    assert run["seed_file"]["regions"] == [{"name": "precentral", "vertices": int((REGION == 1).sum())}]


@pytest.mark.skipif(shutil.which("wb_command") is None, reason="Connectome Workbench (wb_command) is not installed")
def test_workbench_reads_the_compressed_gifti_output(files, tmp_path):
    # Connectome Workbench is a reference only, never linked.
    expected = reference(region_seeds("precentral")).astype(np.float32)
    shape = tmp_path / "lh.distance.shape.gii"
    run_tool("distance", files["pial"], "--seeds", files["annot"], "--seed-region", "precentral", "-o", shape, "-q")
    for reduction, value in (("MAX", expected.max()), ("MIN", expected.min()), ("MEAN", expected.mean())):
        shown = subprocess.run(["wb_command", "-metric-stats", str(shape), "-reduce", reduction], check=True,
                               stdin=subprocess.DEVNULL, capture_output=True, text=True).stdout
        assert float(shown) == pytest.approx(float(value), rel=1e-5, abs=1e-6), (reduction, shown)


@pytest.mark.parametrize("encoding", ["GIFTI_ENCODING_B64GZ", "GIFTI_ENCODING_B64BIN", "GIFTI_ENCODING_ASCII"])
def test_gifti_surface_and_label_file_to_func_gifti(files, tmp_path, encoding):
    expected = reference(region_seeds("lingual"), files[encoding])
    func = tmp_path / "lh.distance.func.gii"
    run_tool("distance", files[encoding], "--seeds", files["label_gii"], "--seed-region", "lingual", "-o", func, "-q")
    data = nib.load(func).darrays[0].data
    # NiBabel writes ASCII coordinates with 6 decimals: the reference is
    # NiBabel's reading of the same file.
    np.testing.assert_array_equal(data, expected.astype(np.float32))


def test_freesurfer_label_file_seeds_the_same_region(files, tmp_path):
    output = tmp_path / "lh.distance.curv"
    run_tool("distance", files["pial"], "--seeds", files["label"], "-o", output, "-q")
    np.testing.assert_array_equal(nib.freesurfer.read_morph_data(output),
                                  reference(region_seeds("precentral")).astype(np.float32))


def test_per_vertex_files_as_seeds_mask_and_metric(files, tmp_path):
    folder = files["folder"]
    # Seeds: a shape file, non-zero on the lingual region.
    seeds = folder / "seeds.shape.gii"
    nib.save(nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray((REGION == 2).astype(np.float32))]), seeds)
    # The metric: a step costs 1 + height/100 (curv) and the same as .mgz.
    scale = (1.0 + (HEIGHT + 40.0) / 100.0).astype(np.float32)
    curv, mgz = folder / "lh.scale", folder / "lh.scale.mgz"
    nib.freesurfer.write_morph_data(str(curv), scale)
    nib.save(nib.MGHImage(scale.reshape(N, 1, 1), np.eye(4)), mgz)
    expected = reference(np.flatnonzero(REGION == 2), metric="scale", metric_values=scale.astype(np.float64))
    for metric in (curv, mgz):
        output = tmp_path / "d.shape.gii"
        run_tool("distance", files["pial"], "--seeds", seeds, "--metric", f"scale:{metric}", "-o", output, "-q")
        np.testing.assert_array_equal(nib.load(output).darrays[0].data, expected.astype(np.float32))
    # A mask without the precentral region: its vertices are unreached (NaN),
    # and nowhere is the distance shorter than on the whole surface.
    mask = folder / "mask.mgh"
    nib.save(nib.MGHImage((REGION != 1).astype(np.float32).reshape(N, 1, 1), np.eye(4)), mask)
    output = tmp_path / "masked.func.gii"
    run_tool("distance", files["pial"], "--seeds", seeds, "--mask", mask, "-o", output, "-q")
    masked = nib.load(output).darrays[0].data
    whole = reference(np.flatnonzero(REGION == 2)).astype(np.float32)
    assert np.all(np.isnan(masked[REGION == 1]))
    assert np.all(masked[REGION != 1] >= whole[REGION != 1])


def test_the_package_reads_and_writes_the_same_files(files, tmp_path):
    surface = stvd.read_surface(files["pial"])
    coords, faces = nib.freesurfer.read_geometry(files["pial"])
    np.testing.assert_array_equal(surface["vertices"], coords)
    np.testing.assert_array_equal(surface["faces"], faces)
    assert surface["coordinate_space"] == "tkr-RAS" and surface["anatomical_structure"] == "CortexLeft"
    np.testing.assert_allclose(surface["transform"][:3, 3], C_RAS)
    keys, names = stvd.read_surface_regions(files["annot"], N)
    assert names == {0: "unknown", 1: "precentral", 2: "lingual"}
    np.testing.assert_array_equal(keys, REGION)
    gifti_keys, gifti_names = stvd.read_surface_regions(files["label_gii"], N)
    np.testing.assert_array_equal(gifti_keys, REGION)
    assert gifti_names[1] == "precentral"
    seeds = stvd.region_vertices(files["annot"], N, "precentral")
    np.testing.assert_array_equal(seeds, region_seeds("precentral"))
    distance = stvd.surface_distance(surface["vertices"], surface["faces"], seeds)
    np.testing.assert_array_equal(distance, reference(region_seeds("precentral")))
    for name in ("lh.d.shape.gii", "lh.d"):
        stvd.write_surface_values(tmp_path / name, distance, anatomical_structure="CortexLeft",
                                  face_count=len(faces))
    np.testing.assert_array_equal(nib.load(tmp_path / "lh.d.shape.gii").darrays[0].data, distance.astype(np.float32))
    np.testing.assert_array_equal(nib.freesurfer.read_morph_data(tmp_path / "lh.d"), distance.astype(np.float32))
    np.testing.assert_array_equal(stvd.read_surface_values(tmp_path / "lh.d", N), distance.astype(np.float32))
    with pytest.raises(ValueError, match="no region named 'insula'"):
        stvd.region_vertices(files["annot"], N, "insula")


def test_scanner_ras_of_a_rotated_volume_geometry(tmp_path):
    """The transform from tkr-RAS to scanner RAS of a volume that is not
    conformed: NiBabel's vox2ras times the inverse of its vox2ras-tkr."""
    rotation = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])
    affine = np.eye(4)
    affine[:3, :3] = rotation * (0.9, 1.1, 1.3)
    affine[:3, 3] = (-60.0, 12.5, 80.0)
    header = nib.MGHImage(np.zeros((20, 24, 28), np.uint8), affine).header
    info = dict(CONFORMED)
    mdc = header["Mdc"]
    info.update(volume=np.array(header["dims"][:3]), voxelsize=np.array(header["delta"]), xras=mdc[0], yras=mdc[1],
                zras=mdc[2], cras=np.array(header["Pxyz_c"]))
    path = tmp_path / "rh.white"
    nib.freesurfer.write_geometry(str(path), COORDS, FACES, volume_info=info)
    expected = header.get_vox2ras() @ np.linalg.inv(header.get_vox2ras_tkr())
    surface = stvd.read_surface(path)
    assert surface["anatomical_structure"] == "CortexRight"
    np.testing.assert_allclose(surface["transform"], expected, atol=1e-5)


def test_bad_cortical_inputs_are_one_line_errors(files, tmp_path):
    message = tool_message("distance", files["pial"], "--seeds", files["annot"], "--seed-region", "insula", "-o",
                           tmp_path / "d.shape.gii")
    assert "no region named \"insula\"" in message and "precentral" in message
    assert not (tmp_path / "d.shape.gii").exists()
    message = tool_message("distance", files["pial"], "--seeds", files["annot"], "-o", tmp_path / "d.shape.gii")
    assert "--seed-region" in message
    short = tmp_path / "lh.short"
    nib.freesurfer.write_morph_data(str(short), np.ones(N - 1, np.float32))
    message = tool_message("distance", files["pial"], "--seeds", short, "-o", tmp_path / "d.shape.gii")
    assert str(short) in message and f"{N - 1} values for a surface of {N} vertices" in message
    truncated = tmp_path / "lh.truncated"
    truncated.write_bytes(files["pial"].read_bytes()[:5000])
    message = tool_message("distance", truncated, "--seed-vertex", "0", "-o", tmp_path / "d.shape.gii")
    assert str(truncated) in message and "ends in the" in message
    assert not list(tmp_path.glob("d.*"))


def test_region_matrix_and_nearest_region(files, tmp_path):
    """Distances between the annotation's regions and from every vertex to
    the nearest one: each row is its region's own propagation, the nearest
    region the one with the shortest distance; the same from the package
    and whatever the thread count."""
    coords, faces = nib.freesurfer.read_geometry(files["pial"])
    coords = coords.astype(np.float64)
    names = ["unknown", "precentral", "lingual"]
    regions = [np.flatnonzero(REGION == key) for key in range(3)]
    maps = [stvd.surface_distance(coords, faces, r) for r in regions]
    expected = np.array([[0.0 if a == b else maps[a][regions[b]].min() for b in range(3)] for a in range(3)])
    nearest = np.argmin(np.vstack(maps), axis=0)
    matrix_file, nearest_file, output = tmp_path / "m.csv", tmp_path / "lh.nearest.shape.gii", tmp_path / "d.curv"
    for threads in ("1", "2"):
        process = run_tool("distance", files["pial"], "--seeds", files["annot"], "--region-matrix", matrix_file,
                           "--nearest-region", nearest_file, "--threads", threads, "-o", output)
        assert "distances to the nearest of 3 region(s)" in process.stdout
        lines = matrix_file.read_text().splitlines()
        assert lines[1] == "# labels: " + ",".join(names)
        np.testing.assert_allclose(np.loadtxt(matrix_file, delimiter=","), expected, rtol=1e-8)
        keys = nib.load(nearest_file).darrays[0].data
        np.testing.assert_array_equal(keys, nearest.astype(np.float32))
        np.testing.assert_array_equal(nib.freesurfer.read_morph_data(output),
                                      np.vstack(maps).min(axis=0).astype(np.float32))
    # One map per region, the surface built once (the reusable-solver pattern).
    run_tool("distance", files["pial"], "--seeds", files["annot"], "--region-maps", tmp_path / "lh.{region}.shape.gii",
             "-o", output, "-q")
    for name, expected_map in zip(names, maps):
        np.testing.assert_array_equal(nib.load(tmp_path / f"lh.{name}.shape.gii").darrays[0].data,
                                      expected_map.astype(np.float32))
    message = tool_message("distance", files["pial"], "--seeds", files["annot"], "--region-maps", tmp_path / "x.gii",
                           "-o", output)
    assert "{region}" in message
    result = stvd.surface_region_distances(coords, faces, regions, threads=2, keep_maps=True)
    np.testing.assert_array_equal(result["matrix"], expected)
    np.testing.assert_array_equal(result["nearest_region"], nearest)
    np.testing.assert_array_equal(result["maps"], np.vstack(maps))
    # Two named regions only.
    run_tool("distance", files["pial"], "--seeds", files["annot"], "--seed-region", "lingual", "--seed-region",
             "precentral", "--region-matrix", matrix_file, "-o", output, "-q")
    np.testing.assert_allclose(np.loadtxt(matrix_file, delimiter=","), expected[np.ix_([2, 1], [2, 1])], rtol=1e-8)
    message = tool_message("distance", files["pial"], "--seed-vertex", "0", "--region-matrix", matrix_file, "-o",
                           output)
    assert "--region-matrix, --region-maps and --nearest-region need --seeds REGIONS" in message
