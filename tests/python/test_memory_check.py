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
    # The timeout is for a hang, at any load.
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=1200)


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


def test_mesh_runs_that_cannot_fit_raise_memory_error():
    # A surface: a 300 x 300 grid of triangles, Lanthier M = 16 (about 8.6
    # million graph points, some 200 MiB), with 140 MiB left once the arrays
    # exist (the check comes after the surface is built, as in the tool,
    # which takes some 70 MiB of them). A tetrahedral
    # mesh: a 20^3 lattice of Kuhn cubes (41,154 tetrahedra), default STVD,
    # with 4 MiB left.
    run = run_limited("""
        n = 300
        x, y = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float), indexing="ij")
        vertices = np.stack([x.ravel(), y.ravel(), np.zeros(n * n)], axis=1)
        corner = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
        faces = np.concatenate([np.stack([corner, corner + n, corner + n + 1], axis=1),
                                np.stack([corner, corner + n + 1, corner + 1], axis=1)])
        m = 20
        index = lambda i, j, k: (i * m + j) * m + k
        points = np.array([(i, j, k) for i in range(m) for j in range(m) for k in range(m)], dtype=float)
        kuhn = [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7)]
        cube = lambda i, j, k: [index(i + (c >> 2 & 1), j + (c >> 1 & 1), k + (c & 1)) for c in range(8)]
        tetrahedra = np.array([[cube(i, j, k)[c] for c in t] for i in range(m - 1) for j in range(m - 1)
                               for k in range(m - 1) for t in kuhn])
        for name, call, margin in [
                ("surface", lambda: stvd.surface_distance(vertices, faces, [0], method="lanthier", steiner=16),
                 140 << 20),
                ("tet mesh", lambda: stvd.tet_mesh_distance(points, tetrahedra, [0]), 4 << 20)]:
            limit_address_space(margin)
            try:
                call()
                print(name, "no error")
            except MemoryError as e:
                print(name, "MemoryError:", e)
            resource.setrlimit(resource.RLIMIT_AS, (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
    """)
    assert run.returncode == 0, run.stderr
    surface, tets = run.stdout.splitlines()
    assert surface.startswith("surface MemoryError: vertices: the run needs about "), surface
    assert "(90,000 vertices)" in surface and surface.endswith("; pass memory_check=False to run anyway"), surface
    assert tets.startswith("tet mesh MemoryError: tetrahedra: the run needs about "), tets
    assert "(8,000 vertices and 41,154 tetrahedra)" in tets, tets
