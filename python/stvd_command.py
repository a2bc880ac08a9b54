"""The `stvd` command of a pip installation: runs the tool installed with
the package. A module of its own, outside the package stvd, so that the
command needs nothing the package imports (NumPy, NiBabel): `stvd --help`
runs wherever the tool does.

The tool is stvd/_bin/stvd next to this module in a wheel's installation,
tools/stvd of the CMake tree for an editable install (this module then is
that tree's python/stvd_command.py)."""

import os
import pathlib
import sys


def tool_path():
    """The `stvd` tool that belongs to this installation, or None."""
    here = pathlib.Path(__file__).resolve().parent
    for candidate in (here / "stvd" / "_bin" / "stvd", here.parent / "tools" / "stvd"):
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return candidate
    return None


def main():
    tool = tool_path()
    if tool is None:
        print("stvd: the stvd tool is not installed with this package (pip install . builds it; docs/python.md)",
              file=sys.stderr)
        return 2
    os.execv(tool, [str(tool), *sys.argv[1:]])
