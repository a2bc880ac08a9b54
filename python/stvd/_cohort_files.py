"""Output files of a cohort run: written whole or not at all, never over an
input.

Each file is written under a partial name in its own folder, flushed to disk
and renamed over its final name, so a reader (or a re-run) sees the old file
or the new one, never a piece. A process killed while writing leaves only a
partial file, which the run that owns the folder removes
(``remove_partial_files``).
"""

import contextlib
import glob
import hashlib
import os
import secrets

PARTIAL_PREFIX = ".partial-"


def _fsync_folder(folder):
    descriptor = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


@contextlib.contextmanager
def atomic_path(path):
    """A partial path to write ``path`` through: yields it, then flushes the
    written file and renames it over ``path``; on any exception the partial
    file is removed and ``path`` is left as it was. The partial name keeps
    the final name's ending, so writers that choose a format by the
    extension (NiBabel) write the right one."""
    folder, name = os.path.split(os.path.abspath(path))
    partial = os.path.join(folder, f"{PARTIAL_PREFIX}{secrets.token_hex(6)}-{name}")
    try:
        yield partial
        descriptor = os.open(partial, os.O_RDONLY)
        try:
            os.fsync(descriptor)
        finally:
            os.close(descriptor)
        os.replace(partial, path)
        _fsync_folder(folder)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.remove(partial)
        raise


def write_text(path, text):
    """Writes ``text`` (UTF-8) to ``path`` atomically."""
    with atomic_path(path) as partial:
        with open(partial, "w", encoding="utf-8", newline="\n") as file:
            file.write(text)


def remove_partial_files(folder):
    """Removes what writers killed mid-write left in ``folder``; returns how
    many. Only for a folder that no other process of the run writes into."""
    removed = 0
    for partial in glob.glob(os.path.join(glob.escape(folder), PARTIAL_PREFIX + "*")):
        with contextlib.suppress(FileNotFoundError):
            os.remove(partial)
            removed += 1
    return removed


def file_record(path):
    """The size and SHA-256 of a written file, as the statistics keep them."""
    digest = hashlib.sha256()
    with open(path, "rb") as file:
        for block in iter(lambda: file.read(1 << 20), b""):
            digest.update(block)
    return {"bytes": os.path.getsize(path), "sha256": digest.hexdigest()}


def file_identity(path):
    """What makes two spellings the same file: the device and inode of an
    existing file, the canonical path (symlinks resolved) of one that does
    not exist yet."""
    try:
        status = os.stat(path)
        return ("inode", status.st_dev, status.st_ino)
    except FileNotFoundError:
        return ("path", os.path.realpath(path))


def check_outputs_are_not_inputs(outputs, inputs, context):
    """Raises ValueError when an output is one of the inputs, however it is
    spelled (``./x``, ``../dir/x``, a symlink, a hard link), or when two
    outputs are the same file. ``outputs`` and ``inputs`` map a role (for
    the message: "output x", "tensors input of y") to a path; ``context``
    starts the message."""
    by_identity = {}
    for role, path in inputs.items():
        by_identity.setdefault(file_identity(path), (role, path))
        # An input that does not exist is compared by its canonical path too.
        by_identity.setdefault(("path", os.path.realpath(path)), (role, path))
    seen = {}
    for role, path in outputs.items():
        identities = {file_identity(path), ("path", os.path.realpath(path))}
        for identity in identities:
            if identity in by_identity:
                input_role, input_path = by_identity[identity]
                raise ValueError(f"{context}: the {role} ({path}) is the {input_role} ({input_path}); "
                                 "nothing was written")
            if identity in seen:
                raise ValueError(f"{context}: the {seen[identity]} and the {role} are the same file ({path})")
        for identity in identities:
            seen[identity] = role
