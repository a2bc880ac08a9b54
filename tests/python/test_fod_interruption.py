"""Ctrl-C during the FOD table (docs/fod.md, "The tool": "Progress and Ctrl-C
during the table"): `stvd distance FOD --fod-basis NAME` interrupted while it
tabulates F* ends as every interrupted run does (docs/cli.md,
docs/reliability.md "Signals"): killed by SIGINT, which a shell reports as
130, with the one line "stvd: interrupted (SIGINT)" on a cleared line, and
no output, statistics or staging folder left.

The signal is sent at a moment the test observes, never after a delay: the
tool runs with its stderr on a pseudo-terminal, where it draws the table's
progress bar ("FOD table [...] N%"); once a report of the table shows, the
tool is stopped (SIGSTOP), and the test checks that the table was still
running then (the bar not yet erased, no propagation bar after it) before
it sends SIGINT and lets the tool go on. The FOD is large enough (about 4 s
of CPU for the table on one thread of these machines) that this holds at
any load; a run caught after its table (a much faster machine) is repeated
on a larger FOD."""

import os
import pty
import select
import signal
import subprocess
import time

import nibabel as nib
import numpy as np
import pytest

from conftest import TOOL

# tournier07 at lmax 8 (45 coefficients): a positive mean and random lobes,
# so that every voxel is in the domain and has a unit ball to tabulate.
COEFFICIENTS = 45
BAR = b"FOD table ["
PROPAGATION_BAR = b"propagating ["
ERASE = b"\r" + b" " * 72 + b"\r"  # what the tool's bar writes when its operation ends
HANG = 240.0  # seconds: a bound for a hang, not a timing threshold


def write_fod(path, side):
    rng = np.random.default_rng(7)
    coefficients = rng.normal(0.0, 0.15, (side, side, side, COEFFICIENTS)).astype(np.float32)
    coefficients[..., 0] = 1.0
    nib.save(nib.Nifti1Image(coefficients, np.diag([2.0, 2.0, 2.0, 1.0])), path)


class ToolOnATerminal:
    """`stvd` with its stderr on a pseudo-terminal (so that it draws its
    progress bars), its stdout into a file; what it wrote on the terminal
    is collected by read()."""

    def __init__(self, arguments, stdout_path):
        master, slave = pty.openpty()
        self.master, self.text = master, b""
        with open(stdout_path, "wb") as stdout:
            self.process = subprocess.Popen([str(TOOL), *map(str, arguments)], stdin=subprocess.DEVNULL,
                                            stdout=stdout, stderr=slave, start_new_session=True)
        os.close(slave)

    def read(self, until=None):
        """Reads what the tool writes until `until` (bytes) has appeared or
        the terminal closes (the tool ended); returns whether it appeared."""
        deadline = time.monotonic() + HANG
        while until is None or until not in self.text:
            assert time.monotonic() < deadline, f"waited in vain for {until!r}; read {self.text[-200:]!r}"
            ready, _, _ = select.select([self.master], [], [], 1.0)
            if not ready:
                continue
            try:
                chunk = os.read(self.master, 65536)
            except OSError:  # EIO: every writer of the terminal has closed it
                chunk = b""
            if not chunk:
                return False
            self.text += chunk
        return True

    def drain(self):
        """Reads what is already written, without waiting for more."""
        while select.select([self.master], [], [], 0)[0]:
            try:
                chunk = os.read(self.master, 65536)
            except OSError:
                return
            if not chunk:
                return
            self.text += chunk

    def stop(self):
        """SIGSTOP, returning once every thread of the tool is stopped
        (True) or it has ended (False)."""
        self.process.send_signal(signal.SIGSTOP)
        info = os.waitid(os.P_PID, self.process.pid, os.WSTOPPED | os.WEXITED | os.WNOWAIT)
        return info.si_code == os.CLD_STOPPED

    def close(self):
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        os.close(self.master)


def table_still_running(text):
    """Whether the terminal shows the FOD table's bar as the last thing
    drawn: a report of the table, not erased since, and no bar after it."""
    last = text.rfind(BAR)
    return last >= 0 and ERASE not in text[last:] and PROPAGATION_BAR not in text[last:]


@pytest.mark.parametrize("threads", ["1", "2"])
def test_ctrl_c_during_the_fod_table_ends_the_run_cleanly(tmp_path, threads):
    if not TOOL.is_file():
        pytest.skip(f"the stvd tool is not built at {TOOL}")
    out = tmp_path / "out"
    out.mkdir()
    for side in (48, 64):
        for entry in out.iterdir():  # what a run caught too late wrote
            entry.unlink()
        fod = tmp_path / f"fod{side}.nii"
        write_fod(fod, side)
        arguments = ["distance", fod, "--fod-basis", "tournier07", "--seed-voxel", "2,2,2", "--threads", threads,
                     "-o", out / "d.nii.gz", "--stats", out / "d.json"]
        tool = ToolOnATerminal(arguments, tmp_path / "stdout.txt")
        try:
            if not tool.read(until=BAR) or not tool.stop():
                continue  # the table ended before it was drawn or caught: a larger FOD
            tool.drain()
            if not table_still_running(tool.text):
                tool.process.send_signal(signal.SIGCONT)
                assert tool.process.wait() == 0, tool.text
                continue  # caught after the table: a larger FOD
            tool.process.send_signal(signal.SIGINT)
            tool.process.send_signal(signal.SIGCONT)
            tool.read()  # to the end: the terminal closes when the tool has ended
            status = tool.process.wait()
        finally:
            tool.close()
        # Ended by the signal (a shell's 130), after one line on a line of
        # its own: the bar is cleared before it.
        assert status == -signal.SIGINT, (status, tool.text)
        # (The terminal turns "\n" into "\r\n".)
        last_line = tool.text.replace(b"\r\n", b"\n").split(b"\r")[-1]
        assert last_line == b"stvd: interrupted (SIGINT)\n", tool.text[-300:]
        assert (tmp_path / "stdout.txt").read_bytes() == b""
        # No map, no statistics, nothing staged.
        assert sorted(os.listdir(out)) == []
        return
    pytest.fail(f"the table was never caught running; the tool's terminal: {tool.text[-300:]!r}")
