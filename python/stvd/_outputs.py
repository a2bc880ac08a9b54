"""Files written from Python as the ``stvd`` tool writes its own: every
output is compared with every input and with the other outputs by identity
(the same device and inode, or the same canonical path for a file yet to be
written; so ``./x``, ``../dir/x`` and symbolic links are caught) before
anything is written, and the outputs appear together, complete, or not at
all (staged next to their final paths, flushed, then renamed). The checks
and the staging are the library's (``stvd/imaging/run_files.hpp``,
``stvd/system/files/output_transaction.hpp``)."""

import os

from . import _core

FileConflictError = _core.FileConflictError
OutputError = _core.OutputError


def input_file_of(value):
    """The file behind an input: a path, the file a NiBabel image was loaded
    from, or None (an array, an image made in memory)."""
    if value is None:
        return None
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    get_filename = getattr(value, "get_filename", None)
    return get_filename() if get_filename is not None else None


def _pairs(files, name):
    if files is None:
        return []
    items = files.items() if hasattr(files, "items") else files
    pairs = []
    for item in items:
        try:
            role, value = item
        except (TypeError, ValueError):
            raise TypeError(f"{name}: expected a mapping of role to file, or (role, file) pairs") from None
        pairs.append((str(role), value))
    return pairs


def _run_files(outputs, inputs):
    """The library's RunFiles of ``outputs`` and ``inputs`` (see
    ``OutputFiles``), and the output paths as declared."""
    files = _core.RunFiles()
    for role, value in _pairs(inputs, "inputs"):
        path = input_file_of(value)
        if path:
            files.input_image(role, path)  # with the files an image brings; any other file alone
    declared = []
    for role, value in _pairs(outputs, "outputs"):
        if not isinstance(value, (str, os.PathLike)):
            raise TypeError(f"outputs: the {role} must be a path, got {type(value).__name__}")
        path = os.fspath(value)
        if _core.is_image_path(path):
            files.output_image(role, path)
        else:
            files.output_file(role, path)
        declared.append(path)
    return files, declared


def check_outputs_are_not_inputs(outputs, inputs):
    """The identity check of ``OutputFiles`` alone, for outputs whose folders
    are made later (the subject folders of a cohort run): raises
    ``FileConflictError`` when an output is an input or another output;
    writes nothing. Returns the library's RunFiles (``.inputs``: every input
    file with the files it brings, such as a .nhdr's data file)."""
    files = _run_files(outputs, inputs)[0]
    files.check_identities()
    return files


def remove_leftover_staging_folders(folder):
    """Removes the staging folders that writers killed before they could
    clean up (a Dask worker killed mid-task) left in ``folder``; returns how
    many. Only folders demonstrably such leftovers are removed: named and
    owned as ours, holding the record our writers put in each, naming a
    process of this machine that no longer exists
    (``stvd/system/files/output_transaction.hpp``); a live writer's are kept."""
    return _core.remove_leftover_staging_folders(os.fspath(folder))


class OutputFiles:
    """The outputs of one step, checked against its inputs and written all or
    nothing::

        with stvd.OutputFiles({"distance map": "d.nii.gz", "table": "t.csv"},
                              inputs={"tensor input": "dti.nii.gz"}) as out:
            out.write("t.csv", lambda staging: frame.to_csv(staging))
            result.save("d.nii.gz", outputs=out)

    ``outputs`` and ``inputs`` map a role (named in messages) to a file: a
    path, or for inputs a NiBabel image (its file) or None. Creating it
    raises ``stvd.FileConflictError`` (a ValueError) when an output is an
    input or another output, in one line naming both roles ("d.nii.gz: the
    distance map is the tensor input (dti.nii.gz)"), and ``stvd.OutputError``
    (an OSError) when an output's folder is missing or not writable; nothing
    is written then. ``write(path, writer)`` calls ``writer(staging_path)``,
    which must write the file there. Leaving the ``with`` block normally
    moves every output into place; an exception (or ``discard()``) removes
    them all and leaves any file that was at an output path as it was.
    """

    def __init__(self, outputs, inputs=None):
        self._files, self._declared = _run_files(outputs, inputs)
        self._files.check()
        self._transaction = _core.OutputTransaction()
        self._open = True

    @property
    def inputs(self):
        """(role, path) of every input file, companions included."""
        return self._files.inputs

    @property
    def outputs(self):
        """(role, path) of every output file, companions included."""
        return self._files.outputs

    def _declared_output(self, path):
        if not self._open:
            raise ValueError("the outputs were committed or discarded already")
        path = os.fspath(path)
        if path not in self._declared:
            raise ValueError(f"{path}: not one of the outputs declared ({', '.join(self._declared)})")
        return path

    def _require_inputs(self, inputs, what):
        """ValueError unless every (role, file) of ``inputs`` was declared, so
        that the outputs were checked against the files ``what`` read."""
        declared = {path for _, path in self._files.inputs}
        for role, value in inputs:
            path = input_file_of(value)
            if path and path not in declared:
                raise ValueError(f"{path}: the {role} of {what} is not among the inputs of these outputs; "
                                 f"declare them with inputs={what}.input_files")

    def write(self, path, writer):
        """Stages one declared output: ``writer(staging_path)`` writes it."""
        self._transaction.write(self._declared_output(path), writer)

    def write_text(self, path, text):
        """Stages one declared output holding ``text`` (UTF-8, lines ended by
        a newline as given)."""

        def write(staging):
            with open(staging, "w", encoding="utf-8", newline="\n") as file:
                file.write(text)

        self.write(path, write)

    def commit(self):
        """Moves every staged output into place."""
        self._staging_done()
        self._transaction.commit()

    def discard(self):
        """Removes every staged output; nothing appears."""
        self._staging_done()
        self._transaction = None

    def _staging_done(self):
        if not self._open:
            raise ValueError("the outputs were committed or discarded already")
        self._open = False

    def __enter__(self):
        return self

    def __exit__(self, kind, value, traceback):
        if not self._open:
            return False
        if kind is None:
            self.commit()
        else:
            self.discard()
        return False

