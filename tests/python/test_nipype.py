"""stvd.interfaces in a real Nipype workflow: two subjects of the synthetic
cohort through Distance, Path and Connectivity nodes under the MultiProc
plugin, each output checked against the `stvd` tool."""

import os

os.environ.setdefault("NIPYPE_NO_ET", "1")  # no version check over the network

import nibabel as nib  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from nipype import Node, Workflow  # noqa: E402
from nipype.interfaces.io import DataSink, SelectFiles  # noqa: E402
from nipype.interfaces.utility import IdentityInterface  # noqa: E402

from conftest import run_tool  # noqa: E402
from stvd.interfaces import Connectivity, Distance, Path  # noqa: E402
from synthetic_cohort import make_cohort  # noqa: E402

SUBJECTS = ["base", "s02"]
SEED = (19, 18, 11)          # CC_body in the cropped brain
TARGETS = [(32, 14, 7), (5, 15, 8)]  # CST_L, CST_R


@pytest.fixture(scope="module")
def workflow_outputs(tmp_path_factory):
    root = tmp_path_factory.mktemp("nipype")
    data = make_cohort(root / "data", subjects=5, crop=True).parent
    subjects = Node(IdentityInterface(fields=["subject"]), name="subjects")
    subjects.iterables = ("subject", SUBJECTS)
    files = Node(SelectFiles({"tensors": "{subject}/tensors.nii.gz", "mask": "{subject}/mask.nii.gz",
                              "labels": "{subject}/labels.nii.gz"}, base_directory=str(data)), name="files")
    distance = Node(Distance(seed_voxels=[SEED]), name="distance")
    paths = Node(Path(seed_voxels=[SEED], target_voxels=TARGETS), name="paths")
    connectivity = Node(Connectivity(), name="connectivity")
    sink = Node(DataSink(base_directory=str(root / "results"), parameterization=True), name="sink")
    workflow = Workflow(name="stvd_cohort", base_dir=str(root / "work"))
    workflow.connect(subjects, "subject", files, "subject")
    for node in (distance, paths, connectivity):
        workflow.connect(files, "tensors", node, "in_file")
        workflow.connect(files, "mask", node, "mask_file")
        workflow.connect(node, "out_file", sink, f"@{node.name}")
    workflow.connect(files, "labels", connectivity, "labels_file")
    graph = workflow.run(plugin="MultiProc", plugin_args={"n_procs": 2})
    outputs = {}
    for node in graph.nodes():
        if node.name in ("distance", "paths", "connectivity"):
            subject = next(s for s in SUBJECTS if f"_subject_{s}" in node.output_dir())
            outputs[(subject, node.name)] = node.result.outputs.out_file
    return data, outputs


def test_every_node_ran_for_both_subjects(workflow_outputs):
    _, outputs = workflow_outputs
    assert sorted(outputs) == sorted((s, n) for s in SUBJECTS for n in ("connectivity", "distance", "paths"))
    assert all(os.path.isfile(f) for f in outputs.values())


@pytest.mark.parametrize("subject", SUBJECTS)
def test_the_nodes_outputs_are_the_tools(workflow_outputs, subject, tmp_path):
    data, outputs = workflow_outputs
    inputs = [data / subject / "tensors.nii.gz", "--mask", data / subject / "mask.nii.gz"]
    seed = ["--seed-voxel", ",".join(map(str, SEED))]
    run_tool("distance", *inputs, *seed, "-o", tmp_path / "d.nii.gz", "-q")
    assert np.array_equal(np.asanyarray(nib.load(outputs[(subject, "distance")]).dataobj),
                          np.asanyarray(nib.load(tmp_path / "d.nii.gz").dataobj))
    run_tool("connectivity", *inputs, "--labels", data / subject / "labels.nii.gz", "-o", tmp_path / "c.tsv", "-q")
    with open(outputs[(subject, "connectivity")], "rb") as ours:
        assert ours.read() == (tmp_path / "c.tsv").read_bytes()
    targets = [option for t in TARGETS for option in ("--target-voxel", ",".join(map(str, t)))]
    run_tool("path", *inputs, *seed, *targets, "-o", tmp_path / "p.trk", "-q")
    ours, tool = nib.streamlines.load(outputs[(subject, "paths")]), nib.streamlines.load(tmp_path / "p.trk")
    assert len(ours.streamlines) == len(tool.streamlines) == len(TARGETS)
    for a, b in zip(ours.streamlines, tool.streamlines):
        np.testing.assert_allclose(a, b, atol=1e-3)


def test_a_node_never_writes_over_its_input(workflow_outputs, tmp_path):
    data, _ = workflow_outputs
    mask = tmp_path / "mask.nii.gz"
    mask.write_bytes((data / "base" / "mask.nii.gz").read_bytes())
    before = mask.read_bytes()
    node = Distance(in_file=str(data / "base" / "tensors.nii.gz"), mask_file=str(mask), seed_voxels=[SEED],
                    out_file=str(tmp_path / "." / "mask.nii.gz"))
    with pytest.raises(ValueError, match=r"mask\.nii\.gz: the output out_file is the mask_file input"):
        node.run(cwd=str(tmp_path))
    assert mask.read_bytes() == before
