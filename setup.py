"""Builds the Python package stvd for pip: `pip install --no-build-isolation .`

The extension module is the CMake target stvd_python, built in its own
CMake tree (build-python-package/ by default, or the configured tree that
STVD_CMAKE_BUILD_DIR names) for the interpreter that runs pip; the
pure-Python modules come from python/stvd/. See docs/python.md.
"""

import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent
VERSION = re.search(r"project\(stvd VERSION (\S+)", (ROOT / "CMakeLists.txt").read_text()).group(1)
BUILD_BASE = "build-python-package"


class CMakeBuild(build_ext):
    """Configures and builds the project's CMake target stvd_python, then
    puts the module where setuptools expects the extension."""

    def build_extension(self, extension):
        given = os.environ.get("STVD_CMAKE_BUILD_DIR")
        tree = pathlib.Path(given).resolve() if given else ROOT / BUILD_BASE / "cmake"
        if not given:
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(tree), "-DCMAKE_BUILD_TYPE=Release",
                            "-DSTVD_BUILD_TESTS=OFF", "-DSTVD_BUILD_BENCHMARKS=OFF",
                            f"-DPython3_EXECUTABLE={sys.executable}"], check=True)
        subprocess.run(["cmake", "--build", str(tree), "--target", "stvd_python", "-j", str(os.cpu_count() or 1)],
                       check=True)
        built = next((tree / "python" / "stvd").glob("_core*.so"))
        target = pathlib.Path(self.get_ext_fullpath(extension.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(
    name="stvd",
    version=VERSION,
    description="Anisotropic geodesic distances, paths and connectivity for diffusion MRI",
    license="BSD-3-Clause",
    python_requires=">=3.9",
    install_requires=["numpy"],
    packages=["stvd"],
    package_dir={"stvd": "python/stvd"},
    ext_modules=[Extension("stvd._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": BUILD_BASE}, "egg_info": {"egg_base": BUILD_BASE}},
    zip_safe=False,
)
