"""The manifest of a cohort: a TSV file with a header row and one row per
subject, read and checked before anything is computed.

Columns: ``subject``, ``tensors`` and ``labels`` (required), ``mask``,
``tensor_order``, ``tensor_frame`` and ``seeds`` (optional; an empty cell is
no value). Paths are relative to the manifest's folder. Every problem is one
line naming the manifest, the row (its line number in the file, the header
being line 1) and the column.

The whole manifest is checked before any work: a subject id names a folder
and a seed set a file (``distance_<name>.nii.gz``), so both must be names
that are safe on every file system a study folder may live on (``safe_name``).
"""

import csv
import io
import os
import re
from dataclasses import dataclass, field

from . import _core
from ._files import MANIFEST_BYTES, read_regular_text

REQUIRED_COLUMNS = ("subject", "tensors", "labels")
OPTIONAL_COLUMNS = ("mask", "tensor_order", "tensor_frame", "seeds")
PATH_COLUMNS = ("tensors", "labels", "mask", "seeds")
# The names the library declares for its options (without their aliases).
_DECLARED = {d["flag"]: d for d in _core.option_declarations()}
TENSOR_ORDERS = tuple(_DECLARED["--tensor-order"]["choices"])
TENSOR_FRAMES = tuple(_DECLARED["--tensor-frame"]["choices"])

# A subject id names its output folder, and a seed set names a file in it:
# letters, digits, '.', '_' and '-', starting with a letter, a digit or '_'
# (not '.', hidden and our own files'; not '-', an option to every shell tool).
SAFE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9._-]*")
SAFE_NAME_TEXT = "letters, digits, '.', '_' and '-', starting with a letter, a digit or '_'"
# The longest file name (in bytes) the file systems we write on take.
NAME_MAX = 255
# The longest path (in bytes) the system takes.
PATH_MAX = 4095
# Names a subject folder must not have (compared without letter case): the
# files a cohort run writes next to the subject folders, and the names
# Windows file systems (a study folder on an SMB share) reserve for devices.
RUN_FILE_NAMES = ("cohort.tsv", "index.html")
DEVICE_NAMES = ("con", "prn", "aux", "nul") + tuple(f"com{n}" for n in range(1, 10)) + tuple(
    f"lpt{n}" for n in range(1, 10))


def safe_name_problem(name, what, max_bytes=NAME_MAX, reserved=()):
    """Why ``name`` cannot name a ``what`` ("output folder", "output
    file"), or None: not of SAFE_NAME's characters, longer than
    ``max_bytes`` bytes, ending in '.', a device name of Windows, or one of
    ``reserved`` (compared without letter case)."""
    shown = repr(name) if not name.isprintable() else f"'{name}'"
    if len(shown) > 80:
        shown = shown[:60] + "...'"
    if not SAFE_NAME.fullmatch(name):
        return f"{shown} cannot name an {what} ({SAFE_NAME_TEXT})"
    length = len(name.encode("utf-8"))
    if length > max_bytes:
        return f"{shown} is {length} bytes long, more than the {max_bytes} an {what}'s name may have here"
    if name.endswith("."):
        return f"{shown} cannot name an {what} (it ends in '.', which Windows file systems drop)"
    if name.split(".")[0].casefold() in DEVICE_NAMES:
        return f"{shown} cannot name an {what} (a device name on Windows file systems)"
    if name.casefold() in reserved:
        return f"{shown} cannot name an {what}: it is the name of a file the run writes next to it"
    return None


class ManifestError(ValueError):
    """A manifest that cannot be run: one line naming file, row and column."""


@dataclass(frozen=True)
class Subject:
    """One row of the manifest: the subject's id, its input files as absolute
    paths (None where the cell is empty), and the tensor order and frame
    (None: the tool's rules for the file's layout)."""

    id: str
    row: int
    tensors: str
    labels: str
    mask: str = None
    seeds: str = None
    tensor_order: str = None
    tensor_frame: str = None
    cells: dict = field(default_factory=dict, compare=False)

    def inputs(self):
        """The input files by column: ``{'tensors': path, ...}``."""
        return {role: getattr(self, role) for role in PATH_COLUMNS if getattr(self, role) is not None}

    def input_roles(self):
        """The input files as ``stvd.OutputFiles`` takes them: (role, path)."""
        return [(f"{column} input", path) for column, path in self.inputs().items()]


def _where(path, row, column=None):
    return f"{path}, row {row}" + (f", column {column}" if column else "")


def _numbered_rows(path, what, error):
    """The rows of the tab-separated file at ``path`` that are not blank (a
    trailing newline too many carries nothing), each as (line number from
    1, cells); ``error`` (the exception type) "cannot read the <what>" when
    the file cannot be read (or is not a regular file of at most
    MANIFEST_BYTES: a FIFO is never waited on) or is not UTF-8. A cell
    holding a NUL byte is refused naming its row and column."""
    try:
        text = read_regular_text(path, MANIFEST_BYTES)
        lines = list(csv.reader(io.StringIO(text, newline=""), delimiter="\t", quoting=csv.QUOTE_NONE))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        reason = getattr(e, "reason", None) or getattr(e, "strerror", None) or e
        raise error(f"{path}: cannot read the {what}: {reason}") from None
    rows = [(number, cells) for number, cells in enumerate(lines, start=1) if any(c.strip() for c in cells)]
    header = [c.strip() for c in rows[0][1]] if rows else []
    for number, cells in rows:
        for index, cell in enumerate(cells):
            if "\0" in cell:
                column = header[index] if number != rows[0][0] and index < len(header) else f"{index + 1}"
                raise error(f"{_where(path, number, column or index + 1)}: the cell holds a NUL byte")
    return rows


def read_manifest(path):
    """The subjects of the manifest at ``path``, in its order. Raises
    ManifestError for a manifest that cannot be read or run as a whole:
    missing or unknown columns, rows of the wrong length, empty or repeated
    subject ids, ids that cannot name a folder, unknown tensor orders or
    frames. Input files are not opened here: a missing or unreadable input
    is that subject's failure, not the cohort's."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    numbered = _numbered_rows(path, "manifest", ManifestError)
    if not numbered:
        raise ManifestError(f"{path}: the manifest is empty (expected a header row: subject, tensors, labels, ...)")
    header_row, header = numbered[0]
    header = [name.strip() for name in header]
    for name in header:
        if name not in REQUIRED_COLUMNS + OPTIONAL_COLUMNS:
            raise ManifestError(f"{_where(path, header_row, name or '(empty)')}: unknown column (columns: "
                                + ", ".join(REQUIRED_COLUMNS + OPTIONAL_COLUMNS) + ")")
        if header.count(name) > 1:
            raise ManifestError(f"{_where(path, header_row, name)}: the column appears twice")
    for name in REQUIRED_COLUMNS:
        if name not in header:
            raise ManifestError(f"{_where(path, header_row)}: no column '{name}' in the header "
                                "(required: subject, tensors, labels)")
    if len(numbered) == 1:
        raise ManifestError(f"{path}: no subjects (the manifest has only its header row)")

    subjects, rows_by_id, folded = [], {}, {}
    for row, cells in numbered[1:]:
        if len(cells) != len(header):
            raise ManifestError(f"{_where(path, row)}: {len(cells)} cells, but the header has {len(header)} columns")
        values = {name: cell.strip() for name, cell in zip(header, cells)}
        for name in REQUIRED_COLUMNS:
            if not values[name]:
                raise ManifestError(f"{_where(path, row, name)}: empty cell (the column is required)")
        subject = values["subject"]
        problem = safe_name_problem(subject, "output folder", reserved=RUN_FILE_NAMES)
        if problem:
            raise ManifestError(f"{_where(path, row, 'subject')}: {problem}")
        if subject in rows_by_id:
            raise ManifestError(f"{_where(path, row, 'subject')}: '{subject}' is also the subject of row "
                                f"{rows_by_id[subject]}")
        if subject.casefold() in folded:
            other, other_row = folded[subject.casefold()]
            raise ManifestError(f"{_where(path, row, 'subject')}: '{subject}' differs from '{other}' (row "
                                f"{other_row}) only in letter case: one folder on a file system that ignores it")
        rows_by_id[subject] = row
        folded[subject.casefold()] = (subject, row)
        for name in PATH_COLUMNS:
            problem = _path_problem(values.get(name))
            if problem:
                raise ManifestError(f"{_where(path, row, name)}: {problem}")
        for name, allowed in (("tensor_order", TENSOR_ORDERS), ("tensor_frame", TENSOR_FRAMES)):
            if values.get(name) and values[name] not in allowed:
                raise ManifestError(f"{_where(path, row, name)}: '{values[name]}' is not one of "
                                    + ", ".join(allowed))
        files = {name: os.path.normpath(os.path.join(folder, values[name]))
                 for name in PATH_COLUMNS if values.get(name)}
        subjects.append(Subject(id=subject, row=row, tensors=files["tensors"], labels=files["labels"],
                                mask=files.get("mask"), seeds=files.get("seeds"),
                                tensor_order=values.get("tensor_order") or None,
                                tensor_frame=values.get("tensor_frame") or None, cells=values))
    return subjects


def _path_problem(cell):
    """Why a path cell can name no file at all, or None (a file that does
    not exist is the subject's failure, not the manifest's)."""
    if not cell:
        return None
    encoded = cell.encode("utf-8", "surrogateescape")
    longest = max(len(part) for part in encoded.split(b"/"))
    if longest > NAME_MAX:
        return f"the path has a part of {longest} bytes, longer than the {NAME_MAX} a file name may have"
    if len(encoded) > PATH_MAX:
        return f"the path is {len(encoded)} bytes long, longer than the {PATH_MAX} the system takes"
    return None


def read_seed_sets(path, tensors=None):
    """The seed sets of a subject's seeds: a seeds table or a label image.

    A seeds table is a TSV with a header whose columns include ``name``,
    ``i``, ``j`` and ``k`` (0-based voxel indices; other columns, such as
    those of the sample's seeds.tsv, are ignored); rows with the same name
    form one set, ``{name: [(i, j, k), ...]}``. A label image (an image file
    by its extension, on the tensors' grid) gives a set per region: every
    distinct non-zero value, named ``label_<value>``, ``{name: {'label':
    value}}``; its voxels outside the domain are left out (none inside is
    that subject's error). Sets come in the order of first appearance (of
    increasing value for regions); raises ValueError naming file, row and
    column. With ``tensors`` (their file), a label image's header is
    compared with the tensors' grid before its data are read."""
    from . import _core

    if _core.is_image_path(path):
        return _label_seed_sets(path, tensors)
    numbered = _numbered_rows(path, "seeds", ValueError)
    if not numbered:
        raise ValueError(f"{path}: no seeds (expected a header row with name, i, j, k)")
    header_row, header = numbered[0]
    header = [name.strip() for name in header]
    for name in ("name", "i", "j", "k"):
        if name not in header:
            raise ValueError(f"{_where(path, header_row)}: no column '{name}' in the header (required: name, i, j, k)")
    sets, folded = {}, {}
    for row, cells in numbered[1:]:
        if len(cells) != len(header):
            raise ValueError(f"{_where(path, row)}: {len(cells)} cells, but the header has {len(header)} columns")
        values = dict(zip(header, (cell.strip() for cell in cells)))
        name = values["name"]
        if name not in sets:
            # It names the file distance_<name>.nii.gz.
            problem = safe_name_problem(name, "output file", max_bytes=NAME_MAX - len("distance_.nii.gz"))
            if problem:
                raise ValueError(f"{_where(path, row, 'name')}: {problem}")
            other = folded.get(name.casefold())
            if other:
                raise ValueError(f"{_where(path, row, 'name')}: '{name}' differs from '{other[0]}' (row {other[1]}) "
                                 "only in letter case: one file on a file system that ignores it")
            folded[name.casefold()] = (name, row)
        voxel = []
        for axis in ("i", "j", "k"):
            try:
                voxel.append(int(values[axis]))
            except ValueError:
                raise ValueError(f"{_where(path, row, axis)}: '{values[axis]}' is not a voxel index") from None
        sets.setdefault(values["name"], []).append(tuple(voxel))
    if not sets:
        raise ValueError(f"{path}: no seeds (the table has only its header row)")
    return sets


def _label_seed_sets(path, tensors):
    import nibabel
    import numpy as np

    from . import _core
    from ._files import require_regular_file

    # The grid from the headers first: a small .nii.gz can declare billions
    # of voxels, which are not read to be refused (the library's check, which
    # reads no data).
    if tensors is not None:
        _core.require_image_on_grid(path, tensors, "the seed labels are")
    try:
        require_regular_file(path)
        values = np.unique(np.asanyarray(nibabel.load(path).dataobj))
    except Exception as error:  # NiBabel reads NIfTI; another format, or a file it cannot, is this subject's error
        if tensors is not None:
            # A truncated or corrupt file: the library's message, the one
            # stvd.propagate, the Nipype nodes and the tool give for it.
            _core.read_label_image(path, tensors, "the seed labels are")
        raise ValueError(f"{path}: cannot read the seed labels (NIfTI): {' '.join(str(error).split())}") from None
    values = values[values != 0]
    if values.size == 0:
        raise ValueError(f"{path}: no seeds (the label image has no non-zero voxel)")
    if not np.all(np.isfinite(values)) or np.any(values != np.round(values)):
        raise ValueError(f"{path}: seed labels must be integers")
    return {f"label_{int(v)}": {"label": int(v)} for v in values}
