"""Repeated calls do not leak: the resident memory of the process stays flat
over many calls of every kind (after a few to warm up the allocator)."""

import os

import numpy as np

import stvd
from conftest import CC_BODY, CC_BODY_L_LATERAL, DIPY_5D


def resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def calls(dipy_image, components, labels):
    stvd.distance(str(DIPY_5D), CC_BODY)
    stvd.distance(dipy_image, CC_BODY, mask=labels > 0)
    stvd.distance(components, CC_BODY, affine=dipy_image.affine, tensor_order="lower", progress=lambda *r: None)
    result = stvd.propagate(dipy_image, CC_BODY)
    stvd.trace_paths(result, CC_BODY_L_LATERAL)
    try:
        stvd.distance(dipy_image, (0, 0, 0))  # a failure frees what it made, too
    except ValueError:
        pass


def test_resident_memory_stays_flat_over_many_calls(dipy_image, dipy_components):
    labels = np.zeros(dipy_image.shape[:3], np.uint8)
    labels[40:70, 40:70, 5:25] = 1
    for _ in range(2):
        calls(dipy_image, dipy_components, labels)
    before = resident_bytes()
    rounds = 6
    for _ in range(rounds):
        calls(dipy_image, dipy_components, labels)
    growth = resident_bytes() - before
    # A round allocates and frees about 150 MB; a leak of even one distance
    # map (1.6 MB) per call that makes one would add 38 MB over these rounds.
    # Measured: 66.3 MiB resident before and after 12 rounds.
    assert growth < 8 * 2**20, f"resident memory grew by {growth / 2**20:.1f} MiB over {rounds} rounds"
