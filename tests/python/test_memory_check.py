"""A run that cannot fit into the memory left is refused before it starts,
as the tool refuses it (exit code 6): MemoryError, one line naming the
input, nothing computed; memory_check=False is the tool's
--no-memory-check. Each case runs in its own interpreter, whose address
space is limited (ulimit -v) to what it has plus a margin."""

import subprocess
import sys
import textwrap

from conftest import CC_BODY, DIPY_5D

LIMIT = textwrap.dedent("""
    import resource

    def limit_address_space(margin_bytes):
        with open("/proc/self/status") as status:
            size = next(int(line.split()[1]) * 1024 for line in status if line.startswith("VmSize:"))
        resource.setrlimit(resource.RLIMIT_AS, (size + margin_bytes, resource.RLIM_INFINITY))
""")


def run_limited(body):
    script = "import numpy as np\nimport stvd\n" + LIMIT + textwrap.dedent(body)
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)


def test_a_distance_that_cannot_fit_raises_memory_error_naming_the_input():
    # Lanthier's method with M = 16 on the brain needs about 2.5 GiB; 1 GiB
    # is left. Default STVD (about 20 MiB) runs under the same limit.
    run = run_limited(f"""
        limit_address_space(1 << 30)
        try:
            stvd.distance({str(DIPY_5D)!r}, {CC_BODY!r}, method="lanthier", steiner=16)
            print("no error")
        except MemoryError as e:
            print("MemoryError:", e)
        d = stvd.distance({str(DIPY_5D)!r}, {CC_BODY!r})
        print("default run:", int(np.count_nonzero(d.get_fdata() >= 0)))
    """)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0].startswith("MemoryError: " + str(DIPY_5D) + ": the run needs about "), run.stdout
    assert "Lanthier" in lines[0] and "132,892 domain voxels" in lines[0], run.stdout
    assert "(limit: the address-space limit, ulimit -v)" in lines[0], run.stdout
    assert lines[0].endswith("; pass memory_check=False to run anyway"), run.stdout
    assert lines[1] == "default run: 132892", run.stdout


def test_connectivity_counts_the_propagations_that_run_at_once():
    # Four regions on four threads: four propagations of about 20 MiB each
    # at once, with 40 MiB left once the field is read.
    run = run_limited(f"""
        result = stvd.propagate({str(DIPY_5D)!r}, {CC_BODY!r})
        labels = np.zeros(result.shape, np.int16)
        for n, (i, j, k) in enumerate([(55, 54, 15), (60, 54, 15), (50, 60, 15), (55, 40, 15)], start=1):
            labels[i, j, k] = n
        limit_address_space(40 << 20)
        try:
            stvd.connectivity(result, labels, threads=4)
            print("no error")
        except MemoryError as e:
            print("MemoryError:", e)
    """)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("MemoryError: " + str(DIPY_5D) + ": the run needs about "), run.stdout
    assert "(4 propagations at once on 132,892 domain voxels)" in run.stdout, run.stdout


def test_memory_check_false_skips_the_check():
    # The same refused run, unchecked, gets as far as allocating and fails
    # there (std::bad_alloc), not with the check's message.
    run = run_limited(f"""
        limit_address_space(1 << 30)
        try:
            stvd.distance({str(DIPY_5D)!r}, {CC_BODY!r}, method="lanthier", steiner=16, memory_check=False)
            print("no error")
        except MemoryError as e:
            print("MemoryError:", e)
    """)
    assert run.returncode == 0, run.stderr
    assert "pass memory_check=False" not in run.stdout, run.stdout
