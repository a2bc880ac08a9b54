"""How the package's programs (``python -m stvd.report``, ``python -m
stvd.cohort``, which ``stvd report``, ``--report`` and ``stvd cohort`` run)
end when they are told to stop, as the ``stvd`` tool does: SIGINT (Ctrl-C),
SIGTERM (a job scheduler's stop) and SIGHUP raise ``Interrupted`` in the main
thread, so that every ``with`` block on the way out runs (staged outputs are
removed, a cohort's worker processes are stopped and waited for); then the
program says ``stvd: interrupted (SIGTERM)`` and ends by the same signal, so
that a shell sees 130, 143 or 129 and a loop around it stops too. Nothing is
committed after that line: the line comes after the clean-up.

A signal that was ignored when the program started (``nohup``; SIGINT in a
background job of a non-interactive shell) stays ignored. Further signals
while the program cleans up change nothing (Ctrl-C in a terminal reaches the
report child twice: from the terminal, and passed on by the ``stvd`` tool,
which kills it should a second Ctrl-C reach the tool itself); SIGKILL ends
it at once (a cohort's workers then end with it).

For programs only: ``stvd.cohort.run`` and the other calls of the package
install no signal handlers (their caller's Ctrl-C, a KeyboardInterrupt,
unwinds them the same way).
"""

import contextlib
import os
import signal
import sys

TERMINATION_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class Interrupted(BaseException):
    """A termination signal, raised in the main thread (a BaseException,
    like KeyboardInterrupt: ``except Exception`` does not swallow it)."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def end_by_signal(signum):
    """Ends this process by ``signum`` at its default action, as if it had
    not been handled."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    signal.signal(signum, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, [signum])
    os.kill(os.getpid(), signum)
    os._exit(128 + signum)  # not reached


@contextlib.contextmanager
def ending_by_signal(program="stvd"):
    """Runs the body with the termination signals turned into
    ``Interrupted``; on one, prints ``<program>: interrupted (<NAME>)`` on
    stderr once the body has unwound and ends the process by the signal."""
    state = {"interrupted": False}

    def interrupt(signum, frame):
        if state["interrupted"]:  # the clean-up goes on
            return
        state["interrupted"] = True
        raise Interrupted(signum)

    previous = {}
    for signum in TERMINATION_SIGNALS:
        if signal.getsignal(signum) is not signal.SIG_IGN:
            previous[signum] = signal.signal(signum, interrupt)
    try:
        yield
    except Interrupted as interruption:
        with contextlib.suppress(OSError):  # a terminal that hung up, a reader that has gone
            print(f"{program}: interrupted ({signal.Signals(interruption.signum).name})", file=sys.stderr,
                  flush=True)
        end_by_signal(interruption.signum)
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
