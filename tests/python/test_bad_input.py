"""Bad input raises ValueError or TypeError with the tool's one-line
messages, in the package's keyword names (k, not --k), and nothing reachable
from Python crashes the interpreter."""

import re
import subprocess
import sys
import textwrap

import nibabel as nib
import numpy as np
import pytest

import stvd
from conftest import CC_BODY, DIPY_5D, FSL_6, MASK, tool_message


def in_keyword_names(message):
    """The tool's message as the package words it, by the options'
    declarations: a flag with one of its values (or its value's name) is
    keyword=value, a text value quoted (``--method lanthier`` is
    ``method='lanthier'``, ``--steiner M`` is ``steiner=M``), a switch is
    keyword=True, any other flag its keyword."""
    declarations = sorted((d for d in stvd._core.option_declarations() if d["keyword"]),
                          key=lambda d: -len(d["flag"]))

    def worded(match, declaration):
        value = match.group(1)
        if declaration["type"] == "switch":
            return declaration["keyword"] + ("=False" if declaration["keyword_is_negation"] else "=True")
        if value is None or (value not in declaration["choices"] and value != declaration["value_name"]):
            return declaration["keyword"] + (match.group(0)[len(declaration["flag"]):] if value else "")
        quoted = (declaration["type"] in ("choice", "text") and not declaration["keyword_takes_number"]
                  and value != declaration["value_name"])
        return f"{declaration['keyword']}={quoted and repr(value) or value}"

    for declaration in declarations:
        pattern = re.escape(declaration["flag"]) + r"(?![\w-])(?: ([\w.:-]+?)(?=[,;:)]?(?:\s|$)))?"
        message = re.sub(pattern, lambda match, d=declaration: worded(match, d), message)
    return message


def message_of(error_type, call):
    with pytest.raises(error_type) as caught:
        call()
    text = str(caught.value)
    assert "\n" not in text
    return text


@pytest.mark.parametrize("tool_options, keywords", [
    (["--seed-voxel", "200,54,15"], dict(seeds=(200, 54, 15))),
    (["--seed-voxel", "0,0,0"], dict(seeds=(0, 0, 0))),
    (["--seed-point", "500,0,0"], dict(seed_points=(500, 0, 0))),
    (["--seed-voxel", "55,54,15", "--k", "17"], dict(seeds=CC_BODY, k=17)),
    (["--seed-voxel", "55,54,15", "--method", "fast"], dict(seeds=CC_BODY, method="fast")),
    (["--seed-voxel", "55,54,15", "--chain-measure", "mean"], dict(seeds=CC_BODY, chain_measure="mean")),
    (["--seed-voxel", "55,54,15", "--stencil", "27"], dict(seeds=CC_BODY, stencil="27")),
    (["--seed-voxel", "55,54,15", "--method", "dijkstra", "--k", "3"], dict(seeds=CC_BODY, method="dijkstra", k=3)),
    (["--seed-voxel", "55,54,15", "--method", "lanthier"], dict(seeds=CC_BODY, method="lanthier")),
    (["--seed-voxel", "55,54,15", "--tensor-kind", "metric", "--fa-threshold", "0.2"],
     dict(seeds=CC_BODY, tensor_kind="metric", fa_threshold=0.2)),
    (["--seed-voxel", "55,54,15", "--max-anisotropy", "0.5"], dict(seeds=CC_BODY, max_anisotropy=0.5)),
    (["--seed-voxel", "55,54,15", "--tensor-order", "mrtrix"], dict(seeds=CC_BODY, tensor_order="mrtrix")),
    (["--seed-voxel", "55,54,15", "--fa-threshold", "0.99"], dict(seeds=CC_BODY, fa_threshold=0.99)),
    (["--seed-voxel", "55,54,15", "--mask", FSL_6], dict(seeds=CC_BODY, mask=str(FSL_6))),
    (["--seed-voxel", "55,54,15", "--max-distance", "-3"], dict(seeds=CC_BODY, max_distance=-3)),
    (["--seed-voxel", "55,54,15", "--unreachable-value", "1e+300"], dict(seeds=CC_BODY, unreachable_value=1e300)),
    (["--seed-voxel", "55,54,15", "--domain-connectivity", "12"], dict(seeds=CC_BODY, domain_connectivity=12)),
    (["--seed-voxel", "55,54,15", "--domain-connectivity", "26", "--stencil", "18"],
     dict(seeds=CC_BODY, domain_connectivity=26, stencil="18")),
])
def test_messages_are_the_tools_in_keyword_names(tmp_path, tool_options, keywords):
    expected = in_keyword_names(tool_message("distance", DIPY_5D, "-o", tmp_path / "d.nii.gz", *tool_options))
    assert message_of(ValueError, lambda: stvd.distance(str(DIPY_5D), **keywords)) == expected
    assert "--" not in expected


def test_the_keyword_wording_of_the_tools_messages():
    assert in_keyword_names("--k must be between 1 and 16") == "k must be between 1 and 16"
    assert in_keyword_names("--method lanthier needs --steiner M, the Steiner points per cube edge") == (
        "method='lanthier' needs steiner=M, the Steiner points per cube edge")
    assert in_keyword_names("use --stencil 26 or larger; --domain-connectivity 18 joins") == (
        "use stencil='26' or larger; domain_connectivity=18 joins")
    assert in_keyword_names("or go on with --accept-implausible-tensors") == (
        "or go on with accept_implausible_tensors=True")


def test_a_seed_outside_the_domain_says_why():
    assert message_of(ValueError, lambda: stvd.distance(str(DIPY_5D), (0, 0, 0))) == (
        f"{DIPY_5D}: seed voxel (0, 0, 0) lies outside the domain: its tensor is zero (no data there)")


def test_array_inputs_name_the_argument_and_the_problem(dipy_image, dipy_components):
    affine = dipy_image.affine
    assert message_of(ValueError, lambda: stvd.distance(dipy_components, CC_BODY, tensor_order="lower")).startswith(
        "tensors: an array needs affine=")
    assert "does not say its component order" in message_of(
        ValueError, lambda: stvd.distance(dipy_components, CC_BODY, affine=affine))
    assert message_of(ValueError, lambda: stvd.distance(dipy_components[..., :5], CC_BODY, affine=affine,
                                                        tensor_order="lower")) == (
        "tensors: expected an array of shape (X, Y, Z, 6) or (X, Y, Z, 3, 3), got shape (112, 112, 32, 5)")
    assert message_of(TypeError, lambda: stvd.distance(dipy_components.astype(np.int32), CC_BODY, affine=affine,
                                                       tensor_order="lower")) == (
        "tensors: expected float32 or float64 values, got dtype int32")
    assert message_of(TypeError, lambda: stvd.distance(np.full((4, 4, 4, 6), "x"), CC_BODY, affine=np.eye(4),
                                                       tensor_order="lower")).startswith("tensors: expected numbers")
    assert message_of(ValueError, lambda: stvd.distance(dipy_components, CC_BODY, affine=np.eye(3),
                                                        tensor_order="lower")).startswith("affine: expected a 4x4")
    bad = affine.copy()
    bad[0, 0] = np.nan
    assert message_of(ValueError, lambda: stvd.distance(dipy_components, CC_BODY, affine=bad,
                                                        tensor_order="lower")) == (
        "tensors: the affine has a non-finite entry")
    sheared = affine.copy()
    sheared[0, 1] += 1.0
    assert "orthonormal" in message_of(ValueError, lambda: stvd.distance(dipy_components, CC_BODY, affine=sheared,
                                                                         tensor_order="lower"))
    assert message_of(ValueError, lambda: stvd.distance(dipy_image, CC_BODY, affine=affine)).startswith(
        "affine= applies to arrays")


def test_seeds_masks_and_labels_of_the_wrong_kind(dipy_image):
    assert message_of(TypeError, lambda: stvd.distance(dipy_image, (55.0, 54.0, 15.0))).startswith(
        "seeds: voxel indices must be integers, got whole floating-point numbers (dtype float64); points in world "
        "millimetres (RAS+")
    assert message_of(ValueError, lambda: stvd.distance(dipy_image, [(1, 2)])).startswith("seeds: expected (i, j, k)")
    assert message_of(ValueError, lambda: stvd.distance(dipy_image, seed_points=[(np.nan, 0, 0)])) == (
        "seed_points: a point is not finite")
    assert message_of(ValueError, lambda: stvd.distance(dipy_image)) == (
        "no seed: add seeds=, seed_points= or seed_labels=")
    assert message_of(ValueError, lambda: stvd.distance(dipy_image, CC_BODY, mask=np.ones((10, 10, 10)))) == (
        f"mask: the mask is on another grid than {DIPY_5D} (size 10x10x10 differs from 112x112x32)")
    shifted = nib.Nifti1Image(np.ones(dipy_image.shape[:3], np.uint8), dipy_image.affine + np.diag([0, 0, 0, 0]))
    shifted.affine[0, 3] += 5
    shifted = nib.Nifti1Image(np.ones(dipy_image.shape[:3], np.uint8), shifted.affine)
    assert "the mask is on another grid than" in message_of(ValueError,
                                                            lambda: stvd.distance(dipy_image, CC_BODY, mask=shifted))
    assert message_of(ValueError, lambda: stvd.distance(dipy_image, seed_labels=np.zeros(dipy_image.shape[:3]))) == (
        "seed_labels: the seed label image has no non-zero voxel")
    assert message_of(TypeError, lambda: stvd.distance(dipy_image, CC_BODY, progress="yes")).startswith("progress:")
    assert message_of(ValueError, lambda: stvd.distance(str(MASK), CC_BODY)).startswith(f"{MASK}: is a scalar image")
    assert message_of(ValueError, lambda: stvd.distance("/nonexistent/tensors.nii.gz", CC_BODY)).startswith(
        "/nonexistent/tensors.nii.gz: ")


def test_paths_and_connectivity_refuse_what_the_tool_refuses(tmp_path, dipy_image):
    lanthier = stvd.propagate(dipy_image, CC_BODY, method="lanthier", steiner=1, max_distance=5)
    assert message_of(ValueError, lambda: stvd.trace_paths(lanthier, (56, 54, 15))) == (
        "method='lanthier' gives distances but no predecessors, which paths need; use stvd or dijkstra")
    result = stvd.propagate(dipy_image, CC_BODY, max_distance=5)
    assert message_of(ValueError, lambda: stvd.trace_paths(result, (66, 46, 20))) == (
        f"{DIPY_5D}: target voxel (66, 46, 20) is not reachable from the seeds (no path inside the domain "
        "connects them)")
    assert message_of(ValueError, lambda: stvd.trace_paths(result)) == (
        "no target: add targets=, target_points= or target_labels=")
    labels = np.zeros(dipy_image.shape[:3], np.float32)
    labels[55, 54, 15] = 1.5
    # The rule and words of the tool's label reader (stvd/imaging/label_values.hpp).
    assert message_of(ValueError, lambda: stvd.connectivity(result, labels)) == (
        "labels: voxel (55, 54, 15) holds 1.5, which is not an integer (a label image holds integer labels)")
    labels[55, 54, 15] = 1
    assert message_of(ValueError, lambda: stvd.connectivity(result, labels)) == (
        f"labels: fewer than two regions have voxels inside the domain of {DIPY_5D}")
    assert message_of(TypeError, lambda: stvd.trace_paths("not a result", (1, 2, 3))).startswith("result:")


def test_nothing_reachable_from_python_crashes_the_interpreter():
    """Odd calls in a child interpreter: each must raise ValueError or
    TypeError, and the child must end normally."""
    script = textwrap.dedent("""
        import numpy as np, stvd
        eye = np.eye(4)
        good = np.broadcast_to(np.eye(3, dtype=np.float32), (4, 4, 4, 3, 3))
        calls = [
            lambda: stvd.distance(np.zeros((0, 4, 4, 6), np.float32), (0, 0, 0), affine=eye, tensor_order="fsl"),
            lambda: stvd.distance(np.zeros((4, 4, 4, 6), np.float32), (0, 0, 0), affine=eye, tensor_order="fsl"),
            lambda: stvd.distance(good, (4, 0, 0), affine=eye),
            lambda: stvd.distance(good, (-1, 0, 0), affine=eye),
            lambda: stvd.distance(good, (2**40, 0, 0), affine=eye),
            lambda: stvd.distance(good, (0, 0, 0), affine=np.zeros((4, 4))),
            lambda: stvd.distance(good, (0, 0, 0), affine=eye, seed_labels=np.ones((4, 4))),
            lambda: stvd.distance(good, (0, 0, 0), affine=eye, mask=np.ones((4, 4, 5))),
            lambda: stvd.distance(good, (0, 0, 0), affine=eye, mask=[["x"]]),
            lambda: stvd.distance(good, seed_points=[(1e300, 1e300, 1e300)], affine=eye),
            lambda: stvd.distance(good, (0, 0, 0), affine=eye, k=0),
            lambda: stvd.distance(good, (0, 0, 0), affine=eye, steiner=99, method="lanthier"),
            lambda: stvd.distance(good, (0, 0, 0), affine=eye, method="lanthier", steiner=2, stencil="6"),
            lambda: stvd.distance(good, (0, 0, 0), affine=eye, domain_connectivity="x"),
            lambda: stvd.distance(good, (0, 0, 0), affine=eye, domain_connectivity=2**70),
            lambda: stvd.distance(np.full((4, 4, 4, 3, 3), np.nan, np.float32), (0, 0, 0), affine=eye),
            lambda: stvd.distance(np.arange(4 * 4 * 4 * 9, dtype=np.float32).reshape(4, 4, 4, 3, 3), (0, 0, 0),
                                  affine=eye),
            lambda: stvd.distance(None, (0, 0, 0)),
            lambda: stvd.distance(object(), (0, 0, 0), affine=eye),
            lambda: stvd.tet_mesh_distance(np.zeros((4, 3)), [[0, 1, 2, 7]], [0]),
            lambda: stvd.tet_mesh_distance(np.full((4, 3), np.nan), [[0, 1, 2, 3]], [0]),
            lambda: stvd.tet_mesh_distance(np.eye(4)[:, :3], [[0, 1, 2, 3]], [9]),
            lambda: stvd.tet_mesh_distance(np.eye(4)[:, :3], [[0, 1, 2, -3]], [0]),
            lambda: stvd.tet_mesh_distance(np.eye(4)[:, :3], [[0, 1, 2, 3]], [0], tensors=np.ones((4, 6))),
            lambda: stvd.surface_distance(np.eye(3), [[0, 1, 5]], [0]),
            lambda: stvd.surface_distance(np.eye(3), [[0, 1]], [0]),
            lambda: stvd.surface_distance(np.eye(3), [[0, 1, 2]], [0], metric="curvature"),
            lambda: stvd.surface_distance(np.eye(3), [[0, 1, 2]], [0], metric="tensors",
                                          metric_values=np.ones((2, 3, 3))),
        ]
        for n, call in enumerate(calls):
            try:
                call()
            except (ValueError, TypeError) as error:
                assert "\\n" not in str(error), (n, str(error))
            else:
                raise SystemExit(f"call {n} raised nothing")
        print("survived", len(calls))
    """)
    child = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert child.returncode == 0, child.stderr
    assert child.stdout.strip() == "survived 28"
