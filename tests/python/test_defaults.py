"""stvd.defaults are the library's, the ones the `stvd` tool runs with when
an option is not given: per kind of domain for k (volumes, surfaces,
tetrahedral meshes), the chain measure, the stencil, the unreachable value.
Each is compared with what the tool reports having used, so this fails as
soon as the package and the tool disagree."""

import json
import re

import numpy as np
import stvd
from conftest import CC_BODY, DIPY_5D, run_tool
from test_meshes import bumpy_sheet, read_csv_distances, tetrahedralised_box, varying_tensors, write_off, write_tetgen


def test_volume_defaults_are_the_ones_the_tool_reports(tmp_path):
    run_tool("distance", DIPY_5D, "--seed-voxel", ",".join(map(str, CC_BODY)), "-o", tmp_path / "d.nii.gz", "-q",
             "--stats", tmp_path / "stats.json")
    used = json.loads((tmp_path / "stats.json").read_text())["parameters"]
    names = ("method", "k", "chain_measure", "stencil", "domain_connectivity")
    assert tuple(used[n] for n in names) == tuple(getattr(stvd.defaults, n) for n in names)
    result = stvd.propagate(DIPY_5D, CC_BODY)
    assert tuple(getattr(result, n) for n in names) == tuple(used[n] for n in names)
    assert stvd.defaults.k == 6  # the library's choice for volumes (docs/benchmarks.md)


def test_surface_defaults_are_the_ones_the_tool_reports(tmp_path):
    vertices, faces = bumpy_sheet()
    write_off(tmp_path / "sheet.off", vertices, faces)
    run_tool("distance", tmp_path / "sheet.off", "--seed-vertex", "0", "-o", tmp_path / "tool.csv", "-q",
             "--stats", tmp_path / "stats.json")
    used = json.loads((tmp_path / "stats.json").read_text())["parameters"]
    assert (used["method"], used["k"], used["chain_measure"]) == (
        stvd.defaults.method, stvd.defaults.surface_k, stvd.defaults.surface_chain_measure)
    assert stvd.defaults.surface_k == 8  # surfaces need longer chains (docs/surfaces.md)
    # Without k the package runs with the surfaces' k: the tool's numbers,
    # and not those of the volumes' k.
    ours = stvd.surface_distance(vertices, faces, 0)
    assert np.array_equal(ours, read_csv_distances(tmp_path / "tool.csv"))
    assert np.array_equal(ours, stvd.surface_distance(vertices, faces, 0, k=stvd.defaults.surface_k))


def test_tet_mesh_defaults_are_the_ones_the_tool_reports(tmp_path):
    points, tets = tetrahedralised_box((4, 4, 4), (1.0, 1.0, 1.0))
    write_tetgen(tmp_path / "box", points, tets, varying_tensors(points))
    out = run_tool("distance", tmp_path / "box.node", "--seed-vertex", "0", "--tensors", "node", "-o",
                   tmp_path / "tool.csv").stdout
    k = int(re.search(r"STVD k = (\d+)", out).group(1))
    assert k == stvd.defaults.tet_mesh_k


def test_the_unreachable_value_and_the_tensor_options_are_the_tools():
    assert stvd.defaults.unreachable_value == -1.0
    # Unset: diffusion tensors are capped at 100, a metric is taken as given.
    assert stvd.defaults.max_anisotropy is None and stvd.defaults.diffusion_max_anisotropy == 100.0
    assert stvd.defaults.tensor_kind == "diffusion" and stvd.defaults.diffusion_metric == "inverse"
    assert stvd.defaults.accept_implausible_tensors is False
