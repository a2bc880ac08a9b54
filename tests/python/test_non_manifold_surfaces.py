"""Non-manifold surfaces (docs/surfaces.md, "Non-manifold meshes"): the
tool and the package split them into manifold sheets, say so, and join the
sheets again at the split vertices. Two icospheres touching at a vertex (a
bow tie) are the check: the far sphere's distances are the shared vertex's
distance plus the distances from it on one sphere alone, which the package
computes on the manifold sphere. The exact references on real meshes are
in tests/surface/non_manifold_exact_test.cpp."""

import json

import numpy as np
import pytest

import stvd
from conftest import run_tool
from test_cortical_surfaces import icosphere

SPHERE, SPHERE_FACES = icosphere(2, 10.0)
N = len(SPHERE)
TOP = int(np.argmax(SPHERE[:, 2]))
BOTTOM = int(np.argmin(SPHERE[:, 2]))


def bow_tie():
    """The sphere and its copy above it, the copy's lowest vertex the
    sphere's highest (one vertex, two fans of faces)."""
    copy = np.delete(SPHERE + (SPHERE[TOP] - SPHERE[BOTTOM]), BOTTOM, axis=0)
    renumber = N + np.arange(N) - (np.arange(N) > BOTTOM)
    renumber[BOTTOM] = TOP
    vertices = np.vstack([SPHERE, copy])
    faces = np.vstack([SPHERE_FACES, renumber[SPHERE_FACES]])
    return vertices, faces


def write_off(path, vertices, faces):
    lines = ["OFF", f"{len(vertices)} {len(faces)} 0"]
    lines += [f"{x!r} {y!r} {z!r}" for x, y, z in vertices]
    lines += ["3 " + " ".join(map(str, f)) for f in faces]
    path.write_text("\n".join(lines) + "\n")


def expected_bow_tie_distances(seed, **options):
    on_sphere = stvd.surface_distance(SPHERE, SPHERE_FACES, [seed], **options)
    # The far sphere alone, from its lowest vertex (its own vertex numbers;
    # the same coordinates as in the bow tie, bit for bit).
    far_sphere = SPHERE + (SPHERE[TOP] - SPHERE[BOTTOM])
    from_top = stvd.surface_distance(far_sphere, SPHERE_FACES, [BOTTOM], **options)
    far = on_sphere[TOP] + from_top
    far[BOTTOM] = on_sphere[TOP]
    return on_sphere, far


def test_a_bow_tie_runs_and_the_far_sheet_is_reached_through_the_shared_vertex(tmp_path):
    vertices, faces = bow_tie()
    mesh, output, stats = tmp_path / "bow_tie.off", tmp_path / "d.csv", tmp_path / "run.json"
    write_off(mesh, vertices, faces)
    process = run_tool("distance", mesh, "--seed-vertex", BOTTOM, "-o", output, "--stats", stats)
    line = process.stdout.strip()
    assert "\n" not in line and "non-manifold: 0 edge(s) shared by more than two faces" in line, line
    assert "1 vertex(es) split into manifold sheets (1 copies)" in line, line
    run = json.loads(stats.read_text())
    assert run["non_manifold"]["vertices_split"] == 1 and run["non_manifold"]["propagations"] >= 2
    distance = np.loadtxt(output, delimiter=",", skiprows=1)[:, 1]
    near, far = expected_bow_tie_distances(BOTTOM)
    # The near sphere is the sphere alone; the far one is the far sphere
    # alone, started at the shared vertex's distance: exactly so with
    # Dijkstra; STVD's choice between nearly equal candidates depends on
    # rounding, which the offset changes (3 of 161 vertices, at most 0.4 %
    # longer, none shorter than 0.01 %).
    np.testing.assert_array_equal(distance[:N], near)
    renumbered = np.delete(np.arange(N), BOTTOM)
    relative = distance[N:] / far[renumbered] - 1.0
    assert np.mean(np.abs(relative)) < 1e-4 and np.max(np.abs(relative)) < 1e-2 and relative.min() > -1e-4
    run_tool("distance", mesh, "--seed-vertex", BOTTOM, "--method", "dijkstra", "-o", output, "-q")
    dijkstra = np.loadtxt(output, delimiter=",", skiprows=1)[:, 1]
    near, far = expected_bow_tie_distances(BOTTOM, method="dijkstra")
    np.testing.assert_array_equal(dijkstra[:N], near)
    np.testing.assert_allclose(dijkstra[N:], far[renumbered], rtol=1e-12)


def test_the_package_splits_the_same_way(tmp_path):
    vertices, faces = bow_tie()
    distance = stvd.surface_distance(vertices, faces, [BOTTOM], method="dijkstra")
    near, far = expected_bow_tie_distances(BOTTOM, method="dijkstra")
    np.testing.assert_array_equal(distance[:N], near)
    np.testing.assert_allclose(distance[N:], far[np.delete(np.arange(N), BOTTOM)], rtol=1e-12)
    # The package and the tool: the same numbers.
    write_off(tmp_path / "m.off", vertices, faces)
    run_tool("distance", tmp_path / "m.off", "--seed-vertex", BOTTOM, "-o", tmp_path / "d.csv", "-q")
    np.testing.assert_array_equal(stvd.surface_distance(vertices, faces, [BOTTOM]),
                                  np.loadtxt(tmp_path / "d.csv", delimiter=",", skiprows=1)[:, 1])
    with pytest.raises(ValueError, match="does not run on a non-manifold mesh"):
        stvd.surface_distance(vertices, faces, [BOTTOM], method="lanthier", steiner=2)


def test_a_dangling_face_and_an_edge_of_three_faces(tmp_path):
    """A triangle hanging from an edge of the sphere: the sphere's distances
    do not change, and the hanging corner is reached over the edge's ends."""
    a, b = SPHERE_FACES[0][:2]
    tip = (SPHERE[a] + SPHERE[b]) / 2 + (SPHERE[a] + SPHERE[b]) * 0.3
    vertices = np.vstack([SPHERE, tip])
    faces = np.vstack([SPHERE_FACES, [[a, b, N]]])
    mesh, output = tmp_path / "flap.off", tmp_path / "d.csv"
    write_off(mesh, vertices, faces)
    line = run_tool("distance", mesh, "--seed-vertex", BOTTOM, "-o", output).stdout
    assert "non-manifold: 1 edge(s) shared by more than two faces (1 face(s) cut off there)" in line, line
    distance = np.loadtxt(output, delimiter=",", skiprows=1)[:, 1]
    on_sphere = stvd.surface_distance(SPHERE, SPHERE_FACES, [BOTTOM])
    np.testing.assert_array_equal(distance[:N], on_sphere)
    through_ends = min(on_sphere[a] + np.linalg.norm(tip - SPHERE[a]), on_sphere[b] + np.linalg.norm(tip - SPHERE[b]))
    assert distance[N] == pytest.approx(through_ends, rel=1e-6)
