"""The package works where it is installed: by `cmake --install` (into
<prefix>/lib/python3.X/dist-packages) and by `pip install
--no-build-isolation .` (here reusing the configured build tree)."""

import os
import pathlib
import subprocess
import sys

from conftest import CC_BODY, DIPY_5D, REPOSITORY

BUILD = pathlib.Path(os.environ.get("STVD_BUILD_DIR", REPOSITORY / "build"))
CHECK = f"""
import stvd, sys
assert stvd.__file__.startswith(sys.argv[1]), stvd.__file__
image = stvd.distance({str(DIPY_5D)!r}, {CC_BODY})
print(stvd.__version__, round(float(image.get_fdata().max()), 1))
"""


def run_isolated(python_path, tmp_path):
    """Imports stvd with only `python_path` added, from a folder outside the
    source tree, and computes a distance map."""
    environment = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    environment["PYTHONPATH"] = str(python_path)
    child = subprocess.run([sys.executable, "-c", CHECK, str(python_path)], cwd=tmp_path, env=environment,
                           capture_output=True, text=True)
    assert child.returncode == 0, child.stderr
    return child.stdout.split()


def test_cmake_install_puts_the_package_under_the_prefix(tmp_path):
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", str(BUILD), "--prefix", str(prefix)], check=True, capture_output=True)
    site = prefix / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}" / "dist-packages"
    assert sorted(p.name for p in (site / "stvd").iterdir() if p.suffix == ".py") == [
        "__init__.py", "_files.py", "_inputs.py", "_interruption.py", "_manifest.py", "_outputs.py", "_paths.py",
        "_progress.py", "_regions.py", "_report_matrix.py",
        "_report_page.py", "_report_slices.py", "_subject.py", "cohort.py", "interfaces.py", "report.py"]
    version, farthest = run_isolated(site, tmp_path)
    assert farthest == "91.6"
    # The installed tool needs nothing from the build tree: no library of
    # the project's own is loaded from there (the adapters are linked in),
    # and it draws reports with the installed package (nothing on
    # PYTHONPATH, no LD_LIBRARY_PATH).
    libraries = subprocess.run(["ldd", str(prefix / "bin" / "stvd")], check=True, capture_output=True,
                               text=True).stdout
    assert "not found" not in libraries and str(BUILD.resolve()) not in libraries, libraries
    environment = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "LD_LIBRARY_PATH")}
    (tmp_path / "reports").mkdir()
    report = subprocess.run([str(prefix / "bin" / "stvd"), "report", "--index", str(tmp_path / "reports"), "-o",
                             str(tmp_path / "index.html")], cwd=tmp_path, env=environment, capture_output=True,
                            text=True)
    assert report.returncode == 0, report.stderr
    assert "0 subjects" in (tmp_path / "index.html").read_text()


def test_pip_installs_the_package(tmp_path):
    target = tmp_path / "site"
    environment = dict(os.environ, STVD_CMAKE_BUILD_DIR=str(BUILD))
    subprocess.run([sys.executable, "-m", "pip", "install", "--no-build-isolation", "--no-deps", "--no-index",
                    "--target", str(target), str(REPOSITORY)], check=True, capture_output=True, env=environment)
    version, farthest = run_isolated(target, tmp_path)
    assert farthest == "91.6"
