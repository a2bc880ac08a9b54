#!/usr/bin/env bash
# Installs stvd with pip as a user would, from nothing, and times it: a fresh
# virtual environment that sees Debian's packages (NumPy, NiBabel, ...), no
# package index (offline), `pip install -v .` of this checkout with a new
# CMake tree (build-python-package/, removed first), then `stvd --help` and
# `import stvd` from outside the source tree. Not part of scripts/test.sh
# (a whole build: minutes); tests/python/test_installation.py checks the
# same install reusing the configured build tree.
#
#   bash scripts/install_check.sh [VENV_FOLDER]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
venv="${1:-$(mktemp -d)/stvd-venv}"
rm -rf "$root/build-python-package"
/usr/bin/python3 -m venv --system-site-packages "$venv"
export PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1
start=$(date +%s)
"$venv/bin/pip" install -v "$root"
end=$(date +%s)
cd "$(mktemp -d)"
"$venv/bin/stvd" --help | head -3
"$venv/bin/python" -c "import stvd; print('stvd', stvd.__version__, 'from', stvd.__file__)"
echo "pip install took $((end - start)) s (wall); load average: $(cut -d' ' -f1-3 /proc/loadavg)"
