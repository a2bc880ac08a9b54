"""stvd.SurfaceSolver (issue 31, item 14): a surface and its metric built
once and queried with many seed sets, like potpourri3d's
MeshHeatMethodDistanceSolver. Every query is exactly what
stvd.surface_distance gives; many seed sets on several threads give what
one thread gives; paths go from the target to a seed along edges of the
surface, no shorter than the distance."""

import numpy as np
import pytest

import stvd
from test_cortical_surfaces import icosphere
from test_non_manifold_surfaces import BOTTOM, N, bow_tie

VERTICES, FACES = icosphere(3, 20.0)
SEED_SETS = [[0], [5, 17], [100], [641, 3, 250]]


def test_queries_are_the_one_shot_results():
    solver = stvd.SurfaceSolver(VERTICES, FACES)
    assert solver.vertex_count == len(VERTICES)
    for seeds in SEED_SETS:
        np.testing.assert_array_equal(solver.distance(seeds), stvd.surface_distance(VERTICES, FACES, seeds))
    scale = 1.0 + 0.5 * (VERTICES[:, 2] > 0)
    with_metric = stvd.SurfaceSolver(VERTICES, FACES, metric="scale", metric_values=scale, k=4)
    np.testing.assert_array_equal(with_metric.distance([7]),
                                  stvd.surface_distance(VERTICES, FACES, [7], metric="scale", metric_values=scale, k=4))


def test_many_seed_sets_do_not_depend_on_the_threads():
    solver = stvd.SurfaceSolver(VERTICES, FACES)
    one = solver.distances(SEED_SETS, threads=1)
    assert one.shape == (len(SEED_SETS), len(VERTICES))
    np.testing.assert_array_equal(solver.distances(SEED_SETS, threads=2), one)
    np.testing.assert_array_equal(solver.distances(SEED_SETS), one)
    for row, seeds in zip(one, SEED_SETS):
        np.testing.assert_array_equal(row, solver.distance(seeds))
    regions = [np.array(s) for s in SEED_SETS]
    np.testing.assert_array_equal(solver.region_distances(regions, threads=2)["matrix"],
                                  stvd.surface_region_distances(VERTICES, FACES, regions, threads=1)["matrix"])


def test_paths_run_along_the_surface_from_the_target_to_a_seed():
    solver = stvd.SurfaceSolver(VERTICES, FACES)
    distance = solver.distance([0])
    edges = {tuple(sorted(e)) for f in FACES for e in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))}
    index = {tuple(np.round(v, 9)): i for i, v in enumerate(VERTICES)}
    for target, path in zip([641, 300, 0], solver.paths([0], [641, 300, 0])):
        np.testing.assert_array_equal(path[0], VERTICES[target])
        np.testing.assert_array_equal(path[-1], VERTICES[0])
        steps = [index[tuple(np.round(p, 9))] for p in path]
        assert all(tuple(sorted(pair)) in edges for pair in zip(steps, steps[1:]))
        length = np.linalg.norm(np.diff(path, axis=0), axis=1).sum()
        assert length >= distance[target] * (1 - 1e-6)
    with pytest.raises(ValueError, match="targets: vertex 9999 does not exist"):
        solver.paths([0], [9999])


def test_a_non_manifold_surface_and_a_path_across_its_shared_vertex():
    vertices, faces = bow_tie()
    solver = stvd.SurfaceSolver(vertices, faces)
    np.testing.assert_array_equal(solver.distance([BOTTOM]), stvd.surface_distance(vertices, faces, [BOTTOM]))
    far = len(vertices) - 1
    path = solver.paths([BOTTOM], [far])[0]
    assert any(np.array_equal(p, vertices[int(np.argmax(vertices[:N, 2]))]) for p in path)
    np.testing.assert_array_equal(path[-1], vertices[BOTTOM])
