"""Calls from Python: the GIL is released while the library computes,
progress goes to any callable (or a tqdm bar), and a callable can cancel."""

import sys
import threading
import time

import numpy as np
import pytest

import stvd
from conftest import CC_BODY


def test_the_gil_is_released_while_the_library_computes(dipy_image):
    """A Python thread runs while another one is in the library, between its
    first two progress reports on this brain (at the start, and 0.05 s later
    or at the end). The check counts events, not time:
    with the switch interval made long, the computing thread gives up the
    GIL only when the library lets go of it, and the other thread (which
    gives it up at every turn) can then see that the first report has come
    and the second not yet. Were the GIL held, it would see that zero
    times."""
    stvd.distance(dipy_image, CC_BODY)  # warm up
    phase = ["before"]
    seen_between = [0]
    reports = []

    def progress(*report):
        reports.append(report)
        phase[0] = "between" if len(reports) == 1 else "after"

    def watch():
        while phase[0] != "done":
            if phase[0] == "between":
                seen_between[0] += 1
            time.sleep(0)  # lets go of the GIL

    interval = sys.getswitchinterval()
    sys.setswitchinterval(100.0)  # no forced hand-over: the GIL moves only when let go
    watcher = threading.Thread(target=watch)
    try:
        watcher.start()
        stvd.distance(dipy_image, CC_BODY, stencil="98", progress=progress)
    finally:
        phase[0] = "done"
        watcher.join()
        sys.setswitchinterval(interval)
    assert len(reports) >= 2
    assert seen_between[0] > 0


def test_threads_give_the_same_maps_as_one_after_the_other(dipy_image):
    seeds = [CC_BODY, (68, 50, 11), (41, 51, 12), (55, 41, 8)]
    serial = [stvd.distance(dipy_image, s).get_fdata(dtype=np.float32) for s in seeds]
    parallel = [None] * len(seeds)

    def compute(n):
        parallel[n] = stvd.distance(dipy_image, seeds[n]).get_fdata(dtype=np.float32)

    threads = [threading.Thread(target=compute, args=(n,)) for n in range(len(seeds))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(serial, parallel):
        assert np.array_equal(a, b)


def test_a_progress_function_sees_the_front_advance_and_can_cancel(dipy_image):
    calls = []
    result = stvd.propagate(dipy_image, CC_BODY, progress=lambda *report: calls.append(report))
    # At the start, at least every 0.05 s of the run, and at the end with
    # all 132,892 domain voxels finalised.
    assert len(calls) >= 2
    assert calls[0] == (0, 132892, 0.0)
    assert calls[-1][0] == 132892
    assert all(c[1] == 132892 for c in calls)
    assert [c[0] for c in calls] == sorted(c[0] for c in calls)
    assert all(0 <= c[2] <= np.max(result.distance[np.isfinite(result.distance)]) for c in calls)

    # Cancelled at its first report: the result says so and holds no distances.
    cancelled = stvd.propagate(dipy_image, CC_BODY, progress=lambda *report: False)
    assert cancelled.termination == "cancelled"
    assert cancelled.finalized_vertices == 0
    assert np.count_nonzero(cancelled.distance_map().get_fdata() >= 0) == 0


def test_an_exception_in_the_progress_function_reaches_the_caller(dipy_image):
    class Stop(Exception):
        pass

    def fail(*report):
        raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        stvd.distance(dipy_image, CC_BODY, progress=fail)
    with pytest.raises(Stop):
        labels = np.zeros(dipy_image.shape[:3], np.uint8)
        labels[54:57, 53:56, 14:17] = 1
        labels[67:70, 49:52, 10:13] = 2
        stvd.connectivity(dipy_image, labels, progress=fail)


def test_a_progress_function_that_cancels_connectivity_gets_no_table(dipy_image):
    """Cancelled, connectivity raises instead of returning a table whose
    missing rows would read as regions that do not reach each other."""
    labels = np.zeros(dipy_image.shape[:3], np.uint8)
    labels[54:57, 53:56, 14:17] = 1
    labels[67:70, 49:52, 10:13] = 2
    calls = []

    def cancel(*report):
        calls.append(report)
        return False

    with pytest.raises(RuntimeError, match="region connectivity was cancelled"):
        stvd.connectivity(dipy_image, labels, progress=cancel, threads=1)
    assert len(calls) == 1  # the first propagation's first report; nothing ran after it


def test_progress_true_shows_a_tqdm_bar(dipy_image, capsys):
    stvd.distance(dipy_image, CC_BODY, progress=True)
    bar = capsys.readouterr().err
    assert "propagating" in bar and "100%" in bar and "133k/133k" in bar
