"""Exact answers through the Python API: a constant metric against its closed
form on an oblique, anisotropically sampled grid, and seeds given as an
index, a point and a label giving the same map."""

import numpy as np
import pytest

import stvd

SHAPE = (21, 17, 13)
SEED = (10, 8, 6)


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def oblique_affine(spacing):
    affine = np.eye(4)
    affine[:3, :3] = rotation((1.0, -2.0, 0.5), 0.7) * np.asarray(spacing)
    affine[:3, 3] = (-31.5, 12.25, 107.0)
    # NIfTI keeps the spacing in single precision; so does the library.
    return affine


def ras_offsets(affine):
    """RAS displacement of every voxel from the seed, shape SHAPE + (3,)."""
    index = np.stack(np.meshgrid(*map(np.arange, SHAPE), indexing="ij"), -1) - np.asarray(SEED)
    return index @ affine[:3, :3].T


def constant_tensors(g):
    return np.broadcast_to(g, SHAPE + (3, 3)).astype(np.float32)


# A tensor whose long axis is oblique to the RAS axes and to the grid.
LONG = np.array([0.3, -0.8, 0.52]) / np.linalg.norm([0.3, -0.8, 0.52])
G_RAS = 0.6 * np.eye(3) + 3.4 * np.outer(LONG, LONG)


def distance_values(*args, **keywords):
    """The distance map's values: stvd.distance gives a NiBabel image with
    the affine given."""
    return np.asanyarray(stvd.distance(*args, **keywords).dataobj)


def exact(g_ras, affine):
    x = ras_offsets(affine)
    return np.sqrt(np.einsum("...i,ij,...j->...", x, g_ras, x))


@pytest.mark.parametrize("method", ["stvd", "dijkstra"])
def test_a_constant_metric_is_exact_along_the_stencil_rays_and_never_below_its_closed_form(method):
    affine = oblique_affine((1.0, 1.5, 2.0))
    d = distance_values(constant_tensors(G_RAS), SEED, affine=affine, tensor_kind="metric", tensor_frame="world",
                      method=method)
    truth = exact(G_RAS, affine)
    assert d.dtype == np.float32 and d.shape == SHAPE
    assert d[SEED] == 0.0
    # Along each of the 26 stencil directions the straight edge path is a
    # geodesic, and it is what both methods find.
    on_rays = 0
    for step in np.ndindex(3, 3, 3):
        step = np.subtract(step, 1)
        if not step.any():
            continue
        voxel = np.array(SEED) + step
        while all(0 <= voxel[a] < SHAPE[a] for a in range(3)):
            assert d[tuple(voxel)] == pytest.approx(truth[tuple(voxel)], rel=2e-6)
            on_rays += 1
            voxel = voxel + step
    assert on_rays > 100
    # No path is shorter than the straight segment.
    assert np.all(d >= truth * (1 - 2e-6))
    # And STVD comes close everywhere (the C++ tests bound this finely).
    if method == "stvd":
        assert np.mean(d / np.where(truth > 0, truth, 1) - 1) < 0.02


def test_an_isotropic_metric_gives_dijkstras_closed_form_on_the_26_stencil():
    # With G = I, Dijkstra's shortest 26-neighbour path to an index offset
    # with sorted magnitudes a >= b >= c is c diagonal steps of the cube,
    # b - c of a face and a - b along an axis.
    spacing = 1.25
    affine = oblique_affine((spacing,) * 3)
    d = distance_values(constant_tensors(np.eye(3)), SEED, affine=affine, tensor_kind="metric", method="dijkstra")
    index = np.abs(np.stack(np.meshgrid(*map(np.arange, SHAPE), indexing="ij"), -1) - np.asarray(SEED))
    a, b, c = np.moveaxis(-np.sort(-index, axis=-1), -1, 0)
    closed_form = spacing * (c * np.sqrt(3) + (b - c) * np.sqrt(2) + (a - b))
    assert np.allclose(d, closed_form, rtol=2e-6, atol=0)


def test_isotropic_diffusion_tensors_give_the_identity_metric():
    affine = oblique_affine((1.0, 1.5, 2.0))
    diffusion = distance_values(constant_tensors(7e-4 * np.eye(3)), SEED, affine=affine)
    metric = distance_values(constant_tensors(np.eye(3)), SEED, affine=affine, tensor_kind="metric")
    assert np.array_equal(diffusion, metric)


def test_a_seed_as_an_index_a_point_and_a_label_gives_the_same_map():
    affine = oblique_affine((1.0, 1.5, 2.0))
    tensors = constant_tensors(G_RAS)
    options = dict(affine=affine, tensor_kind="metric", tensor_frame="world")
    by_index = distance_values(tensors, SEED, **options)
    centre = affine @ np.append(SEED, 1.0)
    # Any point within half a voxel picks the same voxel.
    near = centre[:3] + affine[:3, :3] @ np.array([0.4, -0.3, 0.45])
    by_point = distance_values(tensors, seed_points=[near], **options)
    lps = centre[:3] * np.array([-1, -1, 1])
    by_lps_point = distance_values(tensors, seed_points=lps, lps=True, **options)
    labels = np.zeros(SHAPE, np.uint8)
    labels[SEED] = 1
    by_label = distance_values(tensors, seed_labels=labels, **options)
    for other in (by_point, by_lps_point, by_label):
        assert np.array_equal(other, by_index)


def test_masked_voxels_are_unreachable_and_hold_the_unreachable_value():
    affine = oblique_affine((1.0, 1.0, 1.0))
    mask = np.ones(SHAPE, bool)
    mask[:, :, :3] = False
    d = distance_values(constant_tensors(np.eye(3)), SEED, affine=affine, tensor_kind="metric", mask=mask)
    assert np.all(d[:, :, :3] == stvd.defaults.unreachable_value)
    assert np.all(d[:, :, 3:] >= 0)
    nan_map = distance_values(constant_tensors(np.eye(3)), SEED, affine=affine, tensor_kind="metric", mask=mask,
                            unreachable_value=np.nan)
    assert np.all(np.isnan(nan_map[:, :, :3]))
