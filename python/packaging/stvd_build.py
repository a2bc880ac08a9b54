"""The build backend of `pip install .` (PEP 517 and PEP 660): the project's
CMake build, made into a wheel with nothing but the standard library, so
that pip needs nothing from a package index to build it (its isolated
build environment stays empty: `requires = []` in pyproject.toml).

What it builds: the CMake targets stvd_python (the extension module) and
stvd_tool (the `stvd` command), nothing else (no tests, benchmarks or
fuzzers), in build-python-package/ under the source tree (git-ignored) or in
the configured tree that STVD_CMAKE_BUILD_DIR names (reused as it is: its
compiled objects are not built again). CMake's output goes to pip's log, so
`pip install -v .` shows its progress. The wheel holds the package
python/stvd/ with the extension, the tool as stvd/_bin/stvd and the console
script `stvd` (python/stvd_command.py), which runs it. An editable install (`pip install -e .`) puts
a .pth file into the environment that names the CMake tree's python/ folder
(where CMake copies the package next to the extension) and writes nothing
into the source folders.
"""

import base64
import hashlib
import os
import pathlib
import re
import subprocess
import sys
import sysconfig
import zipfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
NAME = "stvd"
BUILD_BASE = ROOT / "build-python-package"

# Runtime dependencies, and the optional ones by what needs them (Debian
# packages in parentheses: python3-...).
REQUIRES = ["numpy", "nibabel"]
EXTRAS = {
    "cohort": ["distributed", "cryptography"],   # stvd.cohort on Dask (python3-distributed, python3-cryptography)
    "nipype": ["nipype"],                         # stvd.interfaces (python3-nipype)
    "report": ["matplotlib"],                     # QC pages (python3-matplotlib)
    "pandas": ["pandas"],                         # Connectivity.to_dataframe (python3-pandas)
    "progress": ["tqdm"],                         # progress=True (python3-tqdm)
}
EXTRAS["all"] = sorted({r for requirements in EXTRAS.values() for r in requirements})


def _version():
    return re.search(r"project\(stvd VERSION (\S+)", (ROOT / "CMakeLists.txt").read_text()).group(1)


def _tag():
    """The wheel's tag: this interpreter, its ABI and platform."""
    interpreter = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{interpreter}-{interpreter}-{platform}"


def _dist_info_name():
    return f"{NAME}-{_version()}.dist-info"


def _metadata():
    lines = ["Metadata-Version: 2.1", f"Name: {NAME}", f"Version: {_version()}",
             "Summary: Anisotropic geodesic distances, paths and connectivity for diffusion MRI",
             "License: BSD-3-Clause", "Requires-Python: >=3.9"]
    lines += [f"Requires-Dist: {r}" for r in REQUIRES]
    for extra, requirements in EXTRAS.items():
        lines.append(f"Provides-Extra: {extra}")
        lines += [f"Requires-Dist: {r}; extra == \"{extra}\"" for r in requirements]
    return "\n".join(lines) + "\n"


def _dist_info_files():
    return {
        "METADATA": _metadata(),
        "WHEEL": f"Wheel-Version: 1.0\nGenerator: stvd_build\nRoot-Is-Purelib: false\nTag: {_tag()}\n",
        "entry_points.txt": "[console_scripts]\nstvd = stvd_command:main\n",
    }


def _cmake_tree():
    """(the CMake tree, whether it is the caller's configured one)."""
    given = os.environ.get("STVD_CMAKE_BUILD_DIR")
    return (pathlib.Path(given).resolve(), True) if given else (BUILD_BASE / "cmake", False)


def _run(command):
    # To pip's log: `pip install -v` shows it as it comes.
    print("stvd_build:", " ".join(command), file=sys.stderr, flush=True)
    subprocess.run(command, check=True, stdout=sys.stderr)


def _build():
    """Configures (unless given a tree) and builds the two targets; returns
    the tree."""
    tree, given = _cmake_tree()
    if not given:
        _run(["cmake", "-S", str(ROOT), "-B", str(tree), "-DCMAKE_BUILD_TYPE=Release", "-DSTVD_BUILD_TESTS=OFF",
              "-DSTVD_BUILD_BENCHMARKS=OFF", "-DSTVD_BUILD_FUZZERS=OFF", f"-DPython3_EXECUTABLE={sys.executable}"])
    jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
    _run(["cmake", "--build", str(tree), "--target", "stvd_python", "stvd_tool", "-j", jobs])
    return tree


def _record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"{name},sha256={digest},{len(data)}"


def _write_wheel(wheel_directory, files):
    """files: {archive name: (bytes, executable)}; returns the wheel's name."""
    name = f"{NAME}-{_version()}-{_tag()}.whl"
    dist_info = _dist_info_name()
    for file, text in _dist_info_files().items():
        files[f"{dist_info}/{file}"] = (text.encode(), False)
    record = [_record_line(n, data) for n, (data, _) in files.items()] + [f"{dist_info}/RECORD,,"]
    files[f"{dist_info}/RECORD"] = ("\n".join(record).encode() + b"\n", False)
    path = pathlib.Path(wheel_directory) / name
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as wheel:
        for archive_name, (data, executable) in files.items():
            info = zipfile.ZipInfo(archive_name, date_time=(2020, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = (0o100755 if executable else 0o100644) << 16
            wheel.writestr(info, data)
    return name


# PEP 517 ---------------------------------------------------------------------

def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_editable(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    folder = pathlib.Path(metadata_directory) / _dist_info_name()
    folder.mkdir(parents=True, exist_ok=True)
    for file, text in _dist_info_files().items():
        (folder / file).write_text(text)
    return folder.name


prepare_metadata_for_build_editable = prepare_metadata_for_build_wheel


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    tree = _build()
    files = {}
    for module in sorted((ROOT / "python" / "stvd").glob("*.py")):
        files[f"stvd/{module.name}"] = (module.read_bytes(), False)
    extension = next((tree / "python" / "stvd").glob("_core*.so"))
    files[f"stvd/{extension.name}"] = (extension.read_bytes(), False)
    files["stvd/_bin/stvd"] = ((tree / "tools" / "stvd").read_bytes(), True)
    files["stvd_command.py"] = ((ROOT / "python" / "stvd_command.py").read_bytes(), False)
    return _write_wheel(wheel_directory, files)


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    tree = _build()
    return _write_wheel(wheel_directory, {"stvd_editable.pth": (f"{tree / 'python'}\n".encode(), False)})
