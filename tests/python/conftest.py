"""What the Python package's tests share: the sample brain, the `stvd` tool
built next to the package, and running it."""

import os
import pathlib
import subprocess

import nibabel as nib
import numpy as np
import pytest

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = pathlib.Path(os.environ.get("STVD_SAMPLE_DATA_DIR", REPOSITORY / "sample_data" / "dti_philips_biobank"))
TOOL = pathlib.Path(os.environ.get("STVD_EXECUTABLE", REPOSITORY / "build" / "tools" / "stvd"))

DIPY_5D = SAMPLE / "dti_tensor_dipy5d.nii.gz"
FSL_6 = SAMPLE / "dti_tensor_fsl6.nii.gz"
TEEM = SAMPLE / "dti_tensor_teem.nrrd"
MASK = SAMPLE / "dti_mask.nii.gz"
FA = SAMPLE / "dti_FA.nii.gz"

# seeds.tsv
CC_BODY = (55, 54, 15)
CC_BODY_RAS = (6.4, 11.6, 76.3)
CC_BODY_R_LATERAL = (49, 54, 16)
CC_BODY_L_LATERAL = (62, 54, 18)
CST_L = (68, 50, 11)
CST_L_LOW = (65, 52, 2)
CST_L_HIGH = (66, 46, 20)


def run_tool(*args, check=True):
    """Runs `stvd` with the arguments; returns the completed process."""
    if not TOOL.is_file():
        raise FileNotFoundError(f"the stvd tool is not built at {TOOL} (set STVD_EXECUTABLE)")
    process = subprocess.run([str(TOOL), *map(str, args)], capture_output=True, text=True)
    if check and process.returncode != 0:
        raise AssertionError(f"stvd {' '.join(map(str, args))} failed ({process.returncode}): {process.stderr}")
    return process


def tool_message(*args):
    """The one-line message of a failing tool run, without its 'stvd: ' prefix."""
    process = run_tool(*args, check=False)
    assert process.returncode not in (0, 1), process.stderr
    line = process.stderr.strip()
    assert "\n" not in line and line.startswith("stvd: "), line
    return line[len("stvd: "):]


def tool_distance(tmp_path, input_path, *options, name="tool.nii.gz"):
    """The tool's distance map (float32 array) for the options."""
    output = tmp_path / name
    run_tool("distance", input_path, "-o", output, "-q", *options)
    return np.asanyarray(nib.load(output).dataobj)


@pytest.fixture(scope="module")
def dipy_image():
    return nib.load(DIPY_5D)


@pytest.fixture(scope="module")
def dipy_components(dipy_image):
    """The DIPY tensors as an (X, Y, Z, 6) float32 array in the 'lower' order
    (the NIfTI SYMMATRIX order the file uses)."""
    return np.asanyarray(dipy_image.dataobj)[:, :, :, 0, :]
