"""The package works where it is installed: by `cmake --install` (into
<prefix>/lib/python3.X/dist-packages) and by `pip install .` (here reusing
the configured build tree): the package, the `stvd` command and the
declared dependencies, offline, in fresh virtual environments, and an
editable install that writes nothing among the sources."""

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
        "__init__.py", "_files.py", "_fod.py", "_inputs.py", "_interruption.py", "_manifest.py", "_outputs.py",
        "_paths.py", "_progress.py", "_regions.py", "_report_matrix.py",
        "_report_page.py", "_report_slices.py", "_subject.py", "cohort.py", "interfaces.py", "report.py"]
    version, farthest = run_isolated(site, tmp_path)
    assert farthest == "91.4"
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


def pip_environment(**extra):
    """pip as offline as CI: no index, no user configuration, nothing on
    PYTHONPATH; the build reuses the configured tree's compiled objects
    (STVD_CMAKE_BUILD_DIR), so that the test takes seconds, not the minutes
    of a build from nothing (which scripts/install_check.sh times)."""
    environment = {k: v for k, v in os.environ.items() if not k.startswith(("PIP_", "PYTHON"))}
    environment.update(PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_CONFIG_FILE=os.devnull,
                       STVD_CMAKE_BUILD_DIR=str(BUILD), **extra)
    return environment


def venv(folder, system_site_packages):
    options = ["--system-site-packages"] if system_site_packages else []
    subprocess.run([sys.executable, "-m", "venv", *options, str(folder)], check=True, capture_output=True)
    return folder / "bin"


def test_pip_installs_the_package_and_the_command_into_a_fresh_venv_offline(tmp_path):
    # The documented command, `pip install .`, with build isolation (pip's
    # default): the backend needs nothing from an index.
    bin_folder = venv(tmp_path / "venv", system_site_packages=True)
    environment = pip_environment()
    install = subprocess.run([str(bin_folder / "pip"), "install", "-v", str(REPOSITORY)], cwd=tmp_path,
                             env=environment, capture_output=True, text=True)
    assert install.returncode == 0, install.stdout[-3000:] + install.stderr[-3000:]
    assert "stvd_build: cmake --build" in install.stdout + install.stderr  # what it builds, shown with -v
    # The command and the package, from outside the source tree.
    help_text = subprocess.run([str(bin_folder / "stvd"), "--help"], cwd=tmp_path, env=environment,
                               capture_output=True, text=True)
    assert help_text.returncode == 0 and "stvd distance" in help_text.stdout, help_text.stderr
    check = subprocess.run([str(bin_folder / "python"), "-c", CHECK, str(tmp_path / "venv")], cwd=tmp_path,
                           env=environment, capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    assert check.stdout.split()[1] == "91.4"
    # The installed tool finds the installed package (stvd report draws with it).
    (tmp_path / "reports").mkdir()
    report = subprocess.run([str(bin_folder / "stvd"), "report", "--index", str(tmp_path / "reports"), "-o",
                             str(tmp_path / "index.html")], cwd=tmp_path, env=environment, capture_output=True,
                            text=True)
    assert report.returncode == 0, report.stderr
    # The declared dependencies.
    metadata = subprocess.run([str(bin_folder / "python"), "-c",
                               "import importlib.metadata as m; print(m.requires('stvd'))"],
                              cwd=tmp_path, env=environment, capture_output=True, text=True, check=True).stdout
    for requirement in ("'numpy'", "'nibabel'", "distributed; extra == \"cohort\"", "pandas; extra == \"pandas\""):
        assert requirement in metadata, metadata


def test_pip_installs_into_a_venv_without_the_system_packages_offline(tmp_path):
    # Without Debian's packages in the venv NumPy and NiBabel cannot come
    # from an index offline: --no-deps installs stvd alone; its command runs.
    bin_folder = venv(tmp_path / "venv", system_site_packages=False)
    environment = pip_environment()
    install = subprocess.run([str(bin_folder / "pip"), "install", "--no-deps", str(REPOSITORY)], cwd=tmp_path,
                             env=environment, capture_output=True, text=True)
    assert install.returncode == 0, install.stdout[-3000:] + install.stderr[-3000:]
    help_text = subprocess.run([str(bin_folder / "stvd"), "--help"], cwd=tmp_path, env=environment,
                               capture_output=True, text=True)
    assert help_text.returncode == 0 and "stvd distance" in help_text.stdout, help_text.stderr


def test_an_editable_install_leaves_nothing_in_the_checkout(tmp_path):
    def untracked():
        return subprocess.run(["git", "status", "--porcelain", "--untracked-files=all", "--", "."],
                              cwd=REPOSITORY, capture_output=True, text=True).stdout

    before = untracked()
    bin_folder = venv(tmp_path / "venv", system_site_packages=True)
    environment = pip_environment()
    install = subprocess.run([str(bin_folder / "pip"), "install", "-e", str(REPOSITORY)], cwd=tmp_path,
                             env=environment, capture_output=True, text=True)
    assert install.returncode == 0, install.stdout[-3000:] + install.stderr[-3000:]
    assert untracked() == before
    # No extension module or egg-info among the sources (ignored or not).
    leftovers = [p for pattern in ("_core*.so", "*.egg-info") for p in (REPOSITORY / "python").rglob(pattern)]
    assert not leftovers, leftovers
    check = subprocess.run([str(bin_folder / "python"), "-c", CHECK, str(BUILD / "python")], cwd=tmp_path,
                           env=environment, capture_output=True, text=True)
    assert check.returncode == 0, check.stderr
    help_text = subprocess.run([str(bin_folder / "stvd"), "--help"], cwd=tmp_path, env=environment,
                               capture_output=True, text=True)
    assert help_text.returncode == 0 and "stvd distance" in help_text.stdout, help_text.stderr
