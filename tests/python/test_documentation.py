"""The snippets of docs/python.md run, one after the other, as the page says
(from a folder that looks like the top of the repository)."""

import contextlib
import io
import os
import re

from conftest import REPOSITORY


def test_the_snippets_of_docs_python_md_run(tmp_path):
    page = (REPOSITORY / "docs" / "python.md").read_text()
    snippets = re.findall(r"^ *```python\n(.*?)^ *```", page, flags=re.S | re.M)
    assert len(snippets) >= 8
    (tmp_path / "sample_data").symlink_to(REPOSITORY / "sample_data")
    (tmp_path / "out").mkdir()
    namespace = {}
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        for snippet in snippets:
            indent = len(snippet) - len(snippet.lstrip(" "))
            code = "\n".join(line[indent:] for line in snippet.splitlines())
            with contextlib.redirect_stdout(io.StringIO()):
                exec(compile(code, "docs/python.md", "exec"), namespace)
    finally:
        os.chdir(here)
    assert (tmp_path / "out" / "cc_paths.trk").is_file()
