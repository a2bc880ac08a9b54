"""The snippets of docs/python.md run, one after the other, as the page says
(from a folder that looks like the top of the repository), the three ways
users run them: pasted into a script file (`python3 snippets.py`), given to
`python3 -c`, and as cells of one interactive session (each executed in
turn in one namespace, as a notebook or IPython does). The cohort snippet
of docs/cohorts.md runs these ways in test_cohort_scripts.py."""

import contextlib
import io
import os
import re
import subprocess
import sys

import pytest

from conftest import REPOSITORY


def snippets():
    page = (REPOSITORY / "docs" / "python.md").read_text()
    found = re.findall(r"^ *```python\n(.*?)^ *```", page, flags=re.S | re.M)
    assert len(found) >= 9
    code = []
    for snippet in found:
        indent = len(snippet) - len(snippet.lstrip(" "))
        code.append("\n".join(line[indent:] for line in snippet.splitlines()))
    return code


@pytest.fixture
def top(tmp_path):
    """A folder that looks like the top of the repository."""
    (tmp_path / "sample_data").symlink_to(REPOSITORY / "sample_data")
    (tmp_path / "out").mkdir()
    return tmp_path


def test_the_snippets_of_docs_python_md_run_as_cells_of_one_session(top):
    namespace = {}
    here = os.getcwd()
    os.chdir(top)
    try:
        for snippet in snippets():
            with contextlib.redirect_stdout(io.StringIO()):
                exec(compile(snippet, "docs/python.md", "exec"), namespace)
    finally:
        os.chdir(here)
    assert (top / "out" / "cc_paths.trk").is_file() and (top / "out" / "dipy_paths.trk").is_file()


@pytest.mark.parametrize("form", ["script file", "python -c"])
def test_the_snippets_of_docs_python_md_run_as_a_program(top, form):
    program = "\n\n".join(snippets()) + "\n"
    if form == "script file":
        (top / "snippets.py").write_text(program)
        command = [sys.executable, "snippets.py"]
    else:
        command = [sys.executable, "-c", program]
    environment = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    process = subprocess.run(command, cwd=top, capture_output=True, text=True, env=environment, timeout=900)
    assert process.returncode == 0, process.stderr[-3000:]
    assert (top / "out" / "cc_paths.trk").is_file() and (top / "out" / "dipy_paths.trk").is_file()
