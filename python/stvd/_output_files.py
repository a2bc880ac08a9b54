"""Output files of the Python entry points: never an input, and never half
written."""

import os
import tempfile


class OutputError(Exception):
    """An output that cannot be written; the message is one line that names
    the file."""


class OutputIsInput(OutputError):
    """An output that names an input file (or another output)."""


def same_file(a, b):
    """Whether two paths name the same file: the same device and inode when
    both exist (hard links, symlinks, ``./x`` and ``../d/x``), the same
    canonical path otherwise."""
    try:
        first, second = os.stat(a), os.stat(b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)
    return (first.st_dev, first.st_ino) == (second.st_dev, second.st_ino)


def check_output(output, inputs):
    """Raises OutputError when ``output`` is one of ``inputs`` (a dict from
    role, such as "tensor", to path; None values are skipped), or when its
    folder does not exist or cannot be written."""
    for role, path in inputs.items():
        if path is not None and same_file(output, path):
            raise OutputIsInput(f"{output}: the output is the {role} input")
    folder = os.path.dirname(os.path.abspath(output))
    if not os.path.isdir(folder):
        raise OutputError(f"{output}: the folder {folder} does not exist")
    if not os.access(folder, os.W_OK):
        raise OutputError(f"{output}: the folder {folder} is not writable")
    if os.path.isdir(output):
        raise OutputError(f"{output}: is a folder")


def write_atomically(path, text):
    """Writes ``text`` (UTF-8) under a temporary name in the same folder and
    renames it into place once complete; on failure nothing is left."""
    folder = os.path.dirname(os.path.abspath(path))
    handle, staging = tempfile.mkstemp(prefix=".stvd-staging-", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as file:
            file.write(text)
            file.flush()
            os.fsync(file.fileno())
        os.chmod(staging, 0o644)
        os.replace(staging, path)
    except BaseException as error:
        try:
            os.unlink(staging)
        except OSError:
            pass
        if isinstance(error, OSError):
            raise OutputError(f"{path}: cannot write: {error.strerror or error}") from error
        raise
