"""No code planted where the data is runs: the Python processes that `stvd
distance --report`, `stvd report` and `stvd cohort` start, and the Dask
workers of stvd.cohort.run, import nothing from the working folder, the
data's folder or the output folder, nor from PYTHONPATH, the user's site
packages (PYTHONUSERBASE) or their .pth files.

Every planted module is a spy: it appends a line to a marker file, then
steps aside for the real module, so that a run that imports it still works
and the marker alone says what ran."""

import os
import pathlib
import subprocess
import sys
import sysconfig
import textwrap

import pytest

import stvd.cohort
from conftest import DIPY_5D, TOOL, run_tool
from synthetic_cohort import make_cohort

# Modules of the standard library and the packages the report and the cohort
# import (json, argparse, socket: also Dask's spawned workers before they
# take their parent's module path), and the package itself.
SPIED_MODULES = ("json", "argparse", "numpy", "socket")

SPY = """\
import importlib, os, sys
with open({marker!r}, "a") as _marker:
    _marker.write(f"{{__name__}} from {{__file__}} in process {{os.getpid()}}\\n")
_here = os.path.dirname(os.path.abspath(__file__))
sys.path[:] = [p for p in sys.path if os.path.abspath(p or ".") != _here]
del sys.modules[__name__]
sys.modules[__name__] = importlib.import_module(__name__)
"""

# The package as a spy: it stands for stvd itself.
PACKAGE_SPY = """\
import importlib, os, sys
with open({marker!r}, "a") as _marker:
    _marker.write(f"package {{__name__}} from {{__file__}} in process {{os.getpid()}}\\n")
_here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:] = [p for p in sys.path if os.path.abspath(p or ".") != _here]
for _name in [m for m in sys.modules if m == "stvd" or m.startswith("stvd.")]:
    del sys.modules[_name]
sys.modules[__name__] = importlib.import_module(__name__)
"""

HOOK = """\
import os
with open({marker!r}, "a") as _marker:
    _marker.write(f"{name} in process {{os.getpid()}}\\n")
"""


def plant(folder, marker):
    """Spies for SPIED_MODULES, the package stvd, sitecustomize and
    usercustomize in ``folder``."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for module in SPIED_MODULES:
        (folder / f"{module}.py").write_text(SPY.format(marker=str(marker)))
    (folder / "stvd").mkdir(exist_ok=True)
    (folder / "stvd" / "__init__.py").write_text(PACKAGE_SPY.format(marker=str(marker)))
    for hook in ("sitecustomize", "usercustomize"):
        (folder / f"{hook}.py").write_text(HOOK.format(marker=str(marker), name=hook))


def user_site(base, marker):
    """A user base (PYTHONUSERBASE) whose site packages hold a .pth file
    that runs code and a usercustomize module."""
    site = pathlib.Path(sysconfig.get_path("purelib", f"{os.name}_user", vars={"userbase": str(base)}))
    site.mkdir(parents=True, exist_ok=True)
    (site / "planted.pth").write_text(f"import os; open({str(marker)!r}, 'a').write('.pth in user site\\n')\n")
    (site / "usercustomize.py").write_text(HOOK.format(marker=str(marker), name="usercustomize in user site"))
    return base


@pytest.fixture
def planted(tmp_path):
    """Folders with spies: ``work`` (the working folder), ``data`` (the
    inputs' folder), ``out`` (the output folder), ``path`` (on PYTHONPATH);
    the environment a user might have (PYTHONPATH, PYTHONUSERBASE,
    PYTHONSTARTUP); and the marker file."""
    marker = tmp_path / "marker.txt"
    folders = {name: tmp_path / name for name in ("work", "data", "out", "path")}
    for folder in folders.values():
        plant(folder, marker)
    startup = tmp_path / "startup.py"
    startup.write_text(HOOK.format(marker=str(marker), name="PYTHONSTARTUP"))
    env = dict(os.environ,
               PYTHONPATH=os.pathsep.join([str(folders["path"]), os.environ.get("PYTHONPATH", "")]),
               PYTHONUSERBASE=str(user_site(tmp_path / "userbase", marker)),
               PYTHONSTARTUP=str(startup))
    return folders, env, marker


def ran(marker):
    return marker.read_text() if marker.exists() else ""


def tool(*args, cwd, env):
    process = subprocess.run([str(TOOL), *map(str, args)], cwd=cwd, env=env, capture_output=True, text=True)
    assert process.returncode == 0, process.stderr
    return process


def test_a_report_child_runs_nothing_planted_where_the_data_is(planted):
    folders, env, marker = planted
    data, out = folders["data"], folders["out"]
    (data / "tensors.nii.gz").write_bytes(DIPY_5D.read_bytes())
    # Working folder, data and outputs apart; then all in one folder, the
    # data's, the usual way of working in a shared study folder.
    tool("distance", data / "tensors.nii.gz", "--seed-voxel", "55,54,15", "-o", out / "d.nii.gz", "--stats",
         out / "d.json", "--report", out / "r.html", "-q", cwd=folders["work"], env=env)
    tool("distance", "tensors.nii.gz", "--seed-voxel", "55,54,15", "-o", "d.nii.gz", "--report", "r.html", "-q",
         cwd=data, env=env)
    tool("report", "--stats", out / "d.json", "-o", out / "again.html", "-q", cwd=folders["work"], env=env)
    tool("report", "--index", out, "-o", folders["work"] / "index.html", "-q", cwd=folders["work"], env=env)
    assert ran(marker) == ""
    for page in (out / "r.html", data / "r.html", out / "again.html", folders["work"] / "index.html"):
        assert page.stat().st_size > 1000


def test_an_interpreter_named_without_a_folder_is_never_taken_from_the_working_folder(planted):
    """STVD_PYTHON=python3 is looked up in the absolute folders of PATH
    only: an empty or relative entry (execvp's working folder) is skipped,
    and a python3 planted in the working folder does not run."""
    folders, env, marker = planted
    work = folders["work"]
    fake = work / "python3"
    fake.write_text(f"#!/bin/sh\necho planted python3 ran >> {marker}\nexit 1\n")
    fake.chmod(0o755)
    (work / "bin").mkdir()
    (work / "bin" / "python3").write_bytes(fake.read_bytes())
    (work / "bin" / "python3").chmod(0o755)
    python_folder = os.path.dirname(os.path.realpath(sys.executable))
    env = dict(env, STVD_PYTHON="python3", PATH=f":bin:{python_folder}:/usr/bin:/bin")
    tool("distance", DIPY_5D, "--seed-voxel", "55,54,15", "-o", "d.nii.gz", "--report", "r.html", "-q",
         cwd=work, env=env)
    assert ran(marker) == ""
    assert (work / "r.html").stat().st_size > 1000


@pytest.mark.parametrize("how", ["tool", "python"])
def test_a_cohort_and_its_dask_workers_run_nothing_planted(planted, tmp_path, how):
    """`stvd cohort` (the working folder being the study's), and
    stvd.cohort.run called from a script elsewhere: its workers are new
    interpreters, which would put their working folder first on the module
    path until they take their parent's."""
    folders, env, marker = planted
    manifest = make_cohort(folders["data"], subjects=4, crop=True)
    plant(manifest.parent, marker)
    outdir = folders["out"] / "study"
    if how == "tool":
        process = subprocess.run([str(TOOL), "cohort", manifest, "-o", outdir, "--workers", "1", "--no-progress"],
                                 cwd=folders["data"], env=env, capture_output=True, text=True)
    else:
        script = tmp_path / "pipeline" / "run_cohort.py"
        script.parent.mkdir()
        script.write_text(textwrap.dedent(f"""\
            import stvd.cohort
            if __name__ == "__main__":
                stvd.cohort.run({str(manifest)!r}, {str(outdir)!r}, workers=1)
            """))
        # The package from the build tree, as a user's PYTHONPATH gives it;
        # the user's own interpreter takes their site packages and startup
        # file as they choose (the workers inherit that choice).
        env = {k: v for k, v in env.items() if k not in ("PYTHONUSERBASE", "PYTHONSTARTUP")}
        env["PYTHONPATH"] = str(pathlib.Path(stvd.cohort.__file__).parents[1])
        process = subprocess.run([sys.executable, script], cwd=folders["data"], env=env, capture_output=True,
                                 text=True)
    assert process.returncode in (0, 3), process.stderr  # 3: the cohort's bad subjects
    assert ran(marker) == ""
    assert (outdir / "index.html").stat().st_size > 1000
    assert (outdir / "base" / "report.html").stat().st_size > 1000
