"""Tetrahedral meshes and surfaces from arrays give the numbers the tool
gives for the same meshes in files."""

import csv
import itertools

import numpy as np
import pytest

import stvd
from conftest import run_tool


def read_csv_distances(path):
    with open(path, newline="") as f:
        return np.array([float(row["distance"]) for row in csv.DictReader(f)])


def tetrahedralised_box(shape, spacing):
    """Points of a grid and each cube cut into six tetrahedra around its main
    diagonal, every tetrahedron positively oriented (as TetGen writes them)."""
    points = np.array(list(itertools.product(*(np.arange(n) * s for n, s in zip(shape, spacing)))))
    index = np.arange(len(points)).reshape(shape)
    tets = []
    for i, j, k in itertools.product(*(range(n - 1) for n in shape)):
        corner = lambda d: index[i + d[0], j + d[1], k + d[2]]
        for path in itertools.permutations(range(3)):
            walk, steps = [0, 0, 0], [corner((0, 0, 0))]
            for axis in path:
                walk[axis] = 1
                steps.append(corner(walk))
            a, b, c, d = steps
            if np.linalg.det(np.array([points[b] - points[a], points[c] - points[a], points[d] - points[a]])) < 0:
                b, c = c, b
            tets.append((a, b, c, d))
    return points, np.array(tets)


def varying_tensors(points):
    """Diffusion-like tensors whose long axis turns with position: (N, 6),
    components xx, xy, xz, yy, yz, zz."""
    angle = points[:, 0] / 8.0
    axis = np.stack([np.cos(angle), np.sin(angle), 0.3 * np.ones_like(angle)], -1)
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    d = 0.3 * np.eye(3) + 1.7 * axis[:, :, None] * axis[:, None, :]
    return np.stack([d[:, 0, 0], d[:, 0, 1], d[:, 0, 2], d[:, 1, 1], d[:, 1, 2], d[:, 2, 2]], -1)


def write_tetgen(base, points, tets, attributes):
    with open(f"{base}.node", "w") as f:
        f.write(f"{len(points)} 3 {attributes.shape[1]} 0\n")
        for n, (p, a) in enumerate(zip(points, attributes)):
            f.write(f"{n} " + " ".join(map(repr, [*p, *a])) + "\n")
    with open(f"{base}.ele", "w") as f:
        f.write(f"{len(tets)} 4 0\n")
        for n, t in enumerate(tets):
            f.write(f"{n} " + " ".join(map(str, t)) + "\n")


@pytest.mark.parametrize("tool_options, keywords", [
    ([], {}),
    (["--method", "dijkstra"], dict(method="dijkstra")),
    (["--k", "3", "--chain-measure", "projection", "--diffusion-metric", "adjugate"],
     dict(k=3, chain_measure="projection", diffusion_metric="adjugate")),
    (["--method", "lanthier", "--steiner", "2"], dict(method="lanthier", steiner=2)),
])
def test_a_tetrahedral_mesh_gives_the_tools_numbers(tmp_path, tool_options, keywords):
    points, tets = tetrahedralised_box((7, 6, 5), (1.0, 1.5, 2.0))
    tensors = varying_tensors(points)
    write_tetgen(tmp_path / "box", points, tets, tensors)
    run_tool("distance", tmp_path / "box.node", "--seed-vertex", "0", "--seed-vertex", "33", "--tensors", "node",
             "-o", tmp_path / "tool.csv", "-q", *tool_options)
    tool = read_csv_distances(tmp_path / "tool.csv")
    ours = stvd.tet_mesh_distance(points, tets, [0, 33], tensors=tensors, tensor_order="fsl", **keywords)
    assert ours.dtype == np.float64 and ours.shape == (len(points),)
    assert np.array_equal(ours, tool)
    matrices = np.zeros((len(points), 3, 3))
    matrices[:, [0, 0, 0, 1, 1, 2], [0, 1, 2, 1, 2, 2]] = tensors
    matrices[:, [1, 2, 2], [0, 0, 1]] = tensors[:, [1, 2, 4]]
    assert np.array_equal(stvd.tet_mesh_distance(points, tets, [0, 33], tensors=matrices, **keywords), tool)


def test_a_mesh_without_tensors_has_the_euclidean_metric():
    points, tets = tetrahedralised_box((5, 5, 5), (1.0, 1.0, 1.0))
    d = stvd.tet_mesh_distance(points, tets, 0, method="dijkstra")
    # Along the edges of the box every path is straight.
    for axis in range(3):
        on_axis = np.flatnonzero(np.all(np.delete(points, axis, axis=1) == 0, axis=1))
        assert np.allclose(d[on_axis], points[on_axis, axis])


def write_off(path, vertices, faces):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(vertices)} {len(faces)} 0\n")
        for v in vertices:
            f.write(" ".join(map(repr, v)) + "\n")
        for face in faces:
            f.write(f"{len(face)} " + " ".join(map(str, face)) + "\n")


def bumpy_sheet(n=14):
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n), indexing="ij")
    vertices = np.stack([x, y, 0.4 * np.exp(-3 * (x ** 2 + y ** 2))], -1).reshape(-1, 3)
    index = np.arange(n * n).reshape(n, n)
    faces = []
    for i, j in itertools.product(range(n - 1), repeat=2):
        faces += [(index[i, j], index[i + 1, j], index[i + 1, j + 1]), (index[i, j], index[i + 1, j + 1], index[i, j + 1])]
    return vertices, np.array(faces)


@pytest.mark.parametrize("tool_options, keywords", [
    ([], {}),
    (["--metric", "curvature", "--anisotropy", "3"], dict(metric="curvature", anisotropy=3)),
    (["--method", "dijkstra"], dict(method="dijkstra")),
    (["--method", "lanthier", "--steiner", "3"], dict(method="lanthier", steiner=3)),
])
def test_a_surface_gives_the_tools_numbers(tmp_path, tool_options, keywords):
    vertices, faces = bumpy_sheet()
    write_off(tmp_path / "sheet.off", vertices, faces)
    run_tool("distance", tmp_path / "sheet.off", "--seed-vertex", "0", "-o", tmp_path / "tool.csv", "-q",
             *tool_options)
    tool = read_csv_distances(tmp_path / "tool.csv")
    ours = stvd.surface_distance(vertices, faces, 0, **keywords)
    assert np.array_equal(ours, tool)


def test_a_surface_takes_per_vertex_tensors_and_polygons(tmp_path):
    vertices, faces = bumpy_sheet()
    tensors = np.tile([4.0, 0.0, 0.0, 1.0, 0.0, 1.0], (len(vertices), 1))  # steps along x cost twice
    table = tmp_path / "tensors.txt"
    np.savetxt(table, tensors)
    write_off(tmp_path / "sheet.off", vertices, faces)
    run_tool("distance", tmp_path / "sheet.off", "--seed-vertex", "5", "--metric", f"tensors:{table}", "-o",
             tmp_path / "tool.csv", "-q")
    ours = stvd.surface_distance(vertices, faces, 5, metric="tensors", metric_values=tensors, tensor_order="fsl")
    assert np.array_equal(ours, read_csv_distances(tmp_path / "tool.csv"))
    # Quads, as a list of polygons, on a flat grid: the surface distance.
    n = 6
    grid = np.array([(i, j, 0.0) for i in range(n) for j in range(n)])
    quads = [[i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1] for i in range(n - 1) for j in range(n - 1)]
    d = stvd.surface_distance(grid, quads, 0, method="dijkstra")
    assert np.allclose(d[:n], np.arange(n))  # along an edge of the grid
