"""A cohort run survives a worker that dies mid-task: a real Dask cluster
(a scheduler and two workers, separate processes on 127.0.0.1, as
`dask-scheduler` and `dask-worker` start them), one worker killed with
SIGKILL while it computes a subject; the outputs must be complete and the
bytes of a serial run, with nothing half-written."""

import os
import signal
import subprocess
import sys
import time

import pytest
from distributed import Client

import stvd.cohort
from conftest import TOOL
from synthetic_cohort import make_cohort
from test_cohort import BAD, folder_bytes, qc_pages


# A bound for a hang, not a time the test expects: a loaded machine starts
# interpreters and runs subjects many times slower than a quiet one.
DEADLINE = 600


def start(module, *args, log):
    """A Dask program (the module that `dask-scheduler` or `dask-worker`
    runs, with this test's interpreter and PYTHONPATH)."""
    return subprocess.Popen([sys.executable, "-m", module, *args], stdout=log, stderr=subprocess.STDOUT)


@pytest.fixture
def dask_cluster(tmp_path):
    """A scheduler and two single-threaded workers without nannies (a killed
    worker stays dead), every port chosen by the system; all stopped at the
    end. Yields (address, {name: process})."""
    scheduler_file = tmp_path / "scheduler.json"
    log = open(tmp_path / "cluster.log", "w")
    # Their HTTP servers too on 127.0.0.1 and a free port: without
    # --dashboard-address, --no-dashboard still serves on every interface
    # (the scheduler on port 8787, which another test run may hold).
    http = ("--no-dashboard", "--dashboard-address", "127.0.0.1:0")
    processes = {"scheduler": start("distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port", "0", *http,
                                    "--scheduler-file", scheduler_file, log=log)}
    try:
        deadline = time.monotonic() + DEADLINE
        while not scheduler_file.exists():
            assert time.monotonic() < deadline, "the scheduler did not start"
            time.sleep(0.1)
        for name in ("victim", "survivor"):
            processes[name] = start("distributed.cli.dask_worker", "--scheduler-file", scheduler_file,
                                    "--name", name, "--nthreads", "1", "--no-nanny", "--host", "127.0.0.1", *http,
                                    log=log)
        with Client(scheduler_file=str(scheduler_file), timeout=f"{DEADLINE}s") as client:
            client.wait_for_workers(2, timeout=DEADLINE)
            yield client, processes
    finally:
        for process in processes.values():
            if process.poll() is None:
                process.terminate()
        for process in processes.values():
            try:
                process.wait(timeout=DEADLINE)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        log.close()
        assert all(p.returncode is not None for p in processes.values())


def executing_subject(client, worker, subjects):
    """The subject of ``subjects`` whose cohort task ``worker`` is executing
    now, or None."""
    stacks = client.call_stack()  # {worker: {key: stack}} of the tasks executing now
    for key in stacks.get(worker, {}):
        for subject in subjects:
            if str(key).startswith(f"stvd-cohort-{subject}-"):
                return subject
    return None


def test_a_worker_killed_mid_task_loses_nothing_and_duplicates_nothing(dask_cluster, tmp_path):
    client, processes = dask_cluster
    cohort = make_cohort(tmp_path / "data", subjects=10, crop=True)
    serial = stvd.cohort.run(cohort, tmp_path / "serial", serial=True)

    workers = client.scheduler_info()["workers"]
    victim = next(address for address, info in workers.items() if info["name"] == "victim")
    outdir = tmp_path / "out"
    run = subprocess.Popen([str(TOOL), "cohort", cohort, "-o", outdir, "--scheduler", client.scheduler_info()["address"],
                            "--no-progress"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        # Kill the victim while it computes a good subject, after at least
        # one subject is complete: mid-run and mid-task.
        good = [s["subject"] for s in serial.subjects if s["subject"] not in BAD]
        killed, deadline = None, time.monotonic() + DEADLINE
        while killed is None:
            assert run.poll() is None, "the run ended before a worker could be killed"
            assert time.monotonic() < deadline
            if any(outdir.glob("*/statistics.json")):
                killed = executing_subject(client, victim, good)
            if killed is None:
                time.sleep(0.02)
        os.kill(processes["victim"].pid, signal.SIGKILL)
        stdout, stderr = run.communicate(timeout=DEADLINE)
    finally:
        if run.poll() is None:
            run.kill()
            run.wait()
    assert processes["victim"].wait(timeout=DEADLINE) == -signal.SIGKILL

    assert run.returncode == 3, stderr  # the two bad subjects
    assert "10 subjects: 10 computed on 2 Dask workers" in stdout
    assert folder_bytes(outdir) == folder_bytes(tmp_path / "serial")
    assert qc_pages(outdir) == qc_pages(tmp_path / "serial")  # a page for every good subject, none for the bad
    assert not list(outdir.rglob(".stvd-staging-*"))
    assert set(stvd.cohort.run(cohort, outdir, serial=True).computed) == BAD  # every other subject complete

    # The subject the victim was computing ran again, on the survivor.
    assert f'"pid": {processes["survivor"].pid}' in (outdir / killed / "run.json").read_text()
