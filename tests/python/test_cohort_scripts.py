"""The docs' cohort snippet works as a user runs it: pasted into a script
without an ``if __name__ == "__main__":`` guard, guarded, and typed in an
interactive session. Dask's workers start with multiprocessing's spawn,
which runs a parent's main script again in every child: the embedded
cluster's workers must not, or each would start the cohort again."""

import os
import pathlib
import re
import subprocess
import sys
import textwrap

import pytest

from conftest import REPOSITORY
from synthetic_cohort import make_cohort

DEADLINE = 600  # seconds: a hang, not a slow machine


def cohort_snippet():
    """The first snippet of docs/cohorts.md, as the page shows it."""
    page = (REPOSITORY / "docs" / "cohorts.md").read_text()
    snippet = re.findall(r"^```python\n(.*?)^```", page, flags=re.S | re.M)[0]
    assert "stvd.cohort.run(" in snippet
    return snippet


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cohort_scripts")
    make_cohort(folder / "study", subjects=4, crop=True)  # base, flipped, seed_outside, corrupt
    return folder


def run_python(folder, arguments):
    environment = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run([sys.executable, *arguments], cwd=folder, capture_output=True, text=True,
                          timeout=DEADLINE, env=environment)


@pytest.mark.parametrize("form", ["script without a guard", "guarded script", "interactive"])
def test_the_cohort_snippet_runs_as_users_run_it(study, form):
    out = study / "out"
    if out.exists():
        import shutil

        shutil.rmtree(out)
    # A line before the call shows whether a worker ran the script again.
    code = 'print("the script runs", flush=True)\n' + cohort_snippet()
    if form == "guarded script":
        code = 'if __name__ == "__main__":\n' + textwrap.indent(code, "    ")
    if form == "interactive":
        process = run_python(study, ["-c", code])
    else:
        (study / "snippet.py").write_text(code)
        process = run_python(study, ["snippet.py"])
    assert process.returncode == 0, process.stderr[-3000:]
    assert process.stdout.count("the script runs") == 1, process.stdout
    assert "another cohort run" not in process.stderr
    # Two of the four subjects fail (a corrupt file, a seed outside the brain).
    assert "['seed_outside', 'corrupt']" in process.stdout, process.stdout
    assert (out / "cohort.tsv").is_file() and (out / "base" / "connectivity.tsv").is_file()
    # The folder's lock is free again: a second run finds everything done.
    again = run_python(study, ["-c", cohort_snippet()])
    assert again.returncode == 0, again.stderr[-3000:]


def test_a_worker_that_imports_the_script_again_says_what_to_add(tmp_path):
    # Another pool than the embedded cluster's (here multiprocessing's own
    # spawn) runs the main script in its child: the call there fails at once
    # with what to add, not on the output folder's lock.
    (tmp_path / "pool.py").write_text(textwrap.dedent("""\
        import multiprocessing
        import os
        import stvd.cohort
        if "STVD_TEST_CHILD" not in os.environ:  # the parent; its children inherit the variable
            os.environ["STVD_TEST_CHILD"] = "1"
            child = multiprocessing.get_context("spawn").Process(target=print, args=("child",))
            child.start()
            child.join()
            print("child exit code", child.exitcode)
        else:
            stvd.cohort.run("manifest.tsv", "out", serial=True)
        """))
    process = run_python(tmp_path, ["pool.py"])
    assert "child exit code 1" in process.stdout, process.stdout + process.stderr
    assert 'Put the call under `if __name__ == "__main__":`' in process.stderr, process.stderr
    assert "another cohort run" not in process.stderr
    assert not (tmp_path / "out").exists()
