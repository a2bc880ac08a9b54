"""`stvd cohort` as a process tree: Ctrl-C (SIGINT to the process group) and
SIGTERM end it by the signal, with one line, after its Dask workers have been
stopped, so that nothing is written after it has said "interrupted"; a
SIGKILL takes the workers with it; and the embedded cluster listens on the
loopback address only (or where --host says).

The runs are stopped at moments the test observes, not after a delay: once
a subject is complete, every worker is frozen (SIGSTOP), and the signal is
sent while they hold their tasks mid-way."""

import operator
import os
import pathlib
import signal
import socket
import subprocess
import time

import pytest

import stvd.cohort
from conftest import TOOL
from synthetic_cohort import make_cohort

SUBJECTS = 12  # more than two workers finish before the test freezes them
DEADLINE = 240  # seconds: a hang, not a slow machine


# ---------------------------------------------------------------------------
# What /proc says about processes and sockets (Linux).

def _stat(pid):
    """(state, ppid, pgrp) of a process, or None when it is gone."""
    try:
        text = pathlib.Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2:].split()
    return fields[0], int(fields[1]), int(fields[2])


def group(pgid):
    """The live processes of a process group (zombies left out)."""
    members = []
    for entry in pathlib.Path("/proc").iterdir():
        if entry.name.isdigit():
            stat = _stat(int(entry.name))
            if stat and stat[2] == pgid and stat[0] not in "ZX":
                members.append(int(entry.name))
    return members


def command_line(pid):
    try:
        return pathlib.Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""


TERMINATION_BITS = sum(1 << (s - 1) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP))


def blocked(pid):
    """The signal mask of a process's main thread (SigBlk), as a number."""
    for line in pathlib.Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("SigBlk:"):
            return int(line.split()[1], 16)
    return 0


def workers_of(pgid):
    """The Dask worker processes of the group (multiprocessing's spawned
    interpreters; not its resource tracker)."""
    return [pid for pid in group(pgid) if "spawn_main" in command_line(pid)]


def _address(hex_address):
    host, port = hex_address.split(":")
    raw = bytes.fromhex(host)
    if len(raw) == 4:
        return socket.inet_ntop(socket.AF_INET, raw[::-1]), int(port, 16)
    words = b"".join(raw[i:i + 4][::-1] for i in range(0, 16, 4))  # four little-endian words
    return socket.inet_ntop(socket.AF_INET6, words), int(port, 16)


def listening(pids):
    """The (address, port) pairs the processes listen on over TCP."""
    inodes = set()
    for pid in pids:
        try:
            for fd in pathlib.Path(f"/proc/{pid}/fd").iterdir():
                with_target = os.readlink(fd)
                if with_target.startswith("socket:["):
                    inodes.add(with_target[8:-1])
        except OSError:
            pass
    found = []
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for line in pathlib.Path(table).read_text().splitlines()[1:]:
            fields = line.split()
            if fields[3] == "0A" and fields[9] in inodes:  # 0A: LISTEN
                found.append(_address(fields[1]))
    return found


def wait_for(condition, what):
    deadline = time.monotonic() + DEADLINE
    while not condition():
        assert time.monotonic() < deadline, f"waited in vain for {what}"
        time.sleep(0.01)


def files_of(folder):
    """Every file under ``folder`` with its size and modification time."""
    return {str(p.relative_to(folder)): (p.stat().st_size, p.stat().st_mtime_ns)
            for p in sorted(pathlib.Path(folder).rglob("*")) if p.is_file()}


# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def manifest(tmp_path_factory):
    return make_cohort(tmp_path_factory.mktemp("cohort"), subjects=SUBJECTS, crop=True)


class Cohort:
    """`stvd cohort MANIFEST -o OUT --workers 2` started in a session of its
    own (the cohort's pid is its process group's id); everything left of
    the group is killed at the end."""

    def __init__(self, manifest, outdir, *options):
        self.outdir = outdir
        self.stderr = outdir.parent / f"{outdir.name}.err"
        with open(self.stderr, "w") as err:
            self.process = subprocess.Popen([str(TOOL), "cohort", manifest, "-o", outdir, "--workers", "2",
                                             "--no-progress", *map(str, options)],
                                            stdout=subprocess.DEVNULL, stderr=err, start_new_session=True)
        self.pgid = self.process.pid

    def freeze_workers_once_a_subject_is_complete(self):
        """Waits for the first complete subject (the cluster is up, the
        workers hold tasks), then stops every worker; returns them."""
        wait_for(lambda: any(self.outdir.glob("*/statistics.json")) or self.process.poll() is not None,
                 "a complete subject")
        assert self.process.poll() is None, "the run ended before it could be interrupted"
        workers = workers_of(self.pgid)
        assert len(workers) == 2, [command_line(p) for p in group(self.pgid)]
        # No termination signal blocked in the run or its workers (the tool
        # blocks them for its signal thread before it becomes Python).
        for pid in [self.pgid, *workers]:
            assert not blocked(pid) & TERMINATION_BITS, (pid, command_line(pid), hex(blocked(pid)))
        for pid in workers:
            os.kill(pid, signal.SIGSTOP)
        wait_for(lambda: all((_stat(pid) or "Z")[0] in "TZX" for pid in workers), "the workers to stop")
        return workers

    def end(self):
        """Lets whatever is left go on, waits until the group is empty
        (multiprocessing's resource tracker ends once everyone else has)."""
        for pid in group(self.pgid):
            os.kill(pid, signal.SIGCONT)
        wait_for(lambda: not group(self.pgid), "every process of the run to end")

    def kill(self):
        for pid in group(self.pgid):
            os.kill(pid, signal.SIGKILL)
        if self.process.poll() is None:
            self.process.wait()


def assert_listening_on(host, addresses):
    """Scheduler, its dashboard, two nannies, two workers and their HTTP
    servers: at least six sockets, all on ``host``."""
    assert len(addresses) >= 6, addresses
    assert {address for address, _ in addresses} == {host}, addresses


@pytest.mark.parametrize("how", ["SIGTERM to the cohort", "Ctrl-C to the process group"])
def test_a_signal_ends_the_run_after_its_workers_and_nothing_is_written_after_it(manifest, tmp_path, how):
    signum = signal.SIGTERM if how.startswith("SIGTERM") else signal.SIGINT
    cohort = Cohort(manifest, tmp_path / "out")
    try:
        workers = cohort.freeze_workers_once_a_subject_is_complete()
        addresses = listening(group(cohort.pgid))
        if signum == signal.SIGTERM:
            os.kill(cohort.pgid, signal.SIGTERM)
        else:
            os.killpg(cohort.pgid, signal.SIGINT)
        # The run ends by the signal (a shell reports 143 or 130), having said so.
        assert cohort.process.wait(timeout=DEADLINE) == -signum
        stderr = cohort.stderr.read_text()
        assert stderr.splitlines()[-1:] == [f"stvd: interrupted ({signal.Signals(signum).name})"], stderr
        # Its workers had ended before it did; nothing it staged is left.
        left = [pid for pid in workers if (_stat(pid) or "Z")[0] not in "ZX"]
        assert not left, "workers outlived the run"
        written = files_of(cohort.outdir)
        assert not [name for name in written if ".stvd-staging-" in name]
        # Nothing appears after the line: not when whatever is left of the
        # group goes on and ends.
        cohort.end()
        assert files_of(cohort.outdir) == written
        # By default the embedded cluster is this machine's only.
        assert_listening_on("127.0.0.1", addresses)
    finally:
        cohort.kill()


def test_a_killed_cohort_takes_its_workers_with_it_and_host_says_where_it_listens(manifest, tmp_path):
    # Another loopback address, so that the test opens nothing to the network.
    cohort = Cohort(manifest, tmp_path / "out", "--host", "127.0.0.2")
    try:
        wait_for(lambda: any(cohort.outdir.glob("*/statistics.json")) or cohort.process.poll() is not None,
                 "a complete subject")
        assert cohort.process.poll() is None, "the run ended before it could be killed"
        assert len(workers_of(cohort.pgid)) == 2
        addresses = listening(group(cohort.pgid))
        os.kill(cohort.pgid, signal.SIGKILL)
        assert cohort.process.wait(timeout=DEADLINE) == -signal.SIGKILL
        wait_for(lambda: not group(cohort.pgid), "the workers to end with the run")
        assert_listening_on("127.0.0.2", addresses)
    finally:
        cohort.kill()


def test_the_embedded_cluster_admits_only_its_own_run():
    """Loopback is every local user's: the cluster talks TLS with keys made
    for the run, and a client with keys of its own is turned away."""
    from distributed import Client
    from distributed.security import Security

    with stvd.cohort._dask_client(None, None, 1, "127.0.0.1") as client:
        address = client.scheduler.address
        assert address.startswith("tls://127.0.0.1:")
        assert client.submit(operator.add, 1, 2).result() == 3  # the run's own client is served
        with pytest.raises(Exception, match="TLS certificate does not match"):
            Client(address, security=Security.temporary(), timeout=f"{DEADLINE}s")


def test_host_is_for_the_embedded_cluster_only(manifest, tmp_path):
    process = subprocess.run([str(TOOL), "cohort", manifest, "-o", tmp_path / "out", "--serial", "--host", "0.0.0.0"],
                             capture_output=True, text=True)
    assert process.returncode == 2
    assert process.stderr == ("stvd: --serial runs in this process: no --scheduler, --workers or --host "
                              "(see stvd cohort --help)\n")
    assert not (tmp_path / "out").exists()
