"""The work of one subject of a cohort, as a worker process runs it: read the
subject's files, compute with the package's public calls (``stvd.propagate``,
``stvd.connectivity``), write the outputs atomically into the subject's
folder, and return a small summary. Arrays never leave the worker: what
travels back to the scheduler is a dict of a few numbers and names.

A task computes some *parts* of a subject: ``'connectivity'`` and its seed
sets (those of a seeds table, or one per region of a seed label image), one
distance map each. By default one task computes all of a subject's parts;
with many seed sets a task per part spreads one subject over the workers.
The outputs of a task are written through the package's ``OutputFiles``,
checked against the subject's inputs and moved into place together when
every part is computed.
"""

import hashlib
import math
import os
import resource
import socket
import time

import numpy as np

from ._files import open_regular_binary, require_regular_file

CONNECTIVITY = "connectivity"
CONNECTIVITY_FILE = "connectivity.tsv"
REPORT_FILE = "report.html"

# The tool's table (stvd connectivity): columns, and numbers with four
# decimals or n/a, so that the cohort's table and the tool's are the same
# bytes (tested).
CONNECTIVITY_COLUMNS = ("region_a", "region_b", "geodesic_mm", "path_mm", "straight_mm", "connectivity",
                        "voxels_a", "voxels_b")


def map_file(seed_set):
    return f"distance_{seed_set}.nii.gz"


def one_line(error):
    """An exception as the one line a cohort table keeps."""
    text = " ".join(str(error).split())
    return text if text else type(error).__name__


def _number(value):
    return f"{value:.4f}" if math.isfinite(value) else "n/a"


def connectivity_table(result):
    """The TSV text of a ``stvd.Connectivity``, as ``stvd connectivity`` writes it."""
    lines = ["\t".join(CONNECTIVITY_COLUMNS)]
    labels, voxels = list(result.labels), list(result.voxels)
    for a in range(len(labels)):
        for b in range(len(labels)):
            if a != b:
                lines.append("\t".join([str(int(labels[a])), str(int(labels[b])),
                                        _number(result.geodesic_mm[a, b]), _number(result.path_mm[a, b]),
                                        _number(result.straight_mm[a, b]), _number(result.connectivity[a, b]),
                                        str(int(voxels[a])), str(int(voxels[b]))]))
    return "\n".join(lines) + "\n"


def _load_tensors(path, tensor_order=None, tensor_frame=None):
    """The tensors as the calls take them: a NIfTI file read once into memory
    (every part of the subject uses it), another file as its path. A file
    NiBabel cannot read is read by the library at once, which raises its
    own message for it: the one the package's calls, the Nipype nodes and
    the tool give for that file."""
    import nibabel

    require_regular_file(path)  # a FIFO named like the tensors is not waited on
    try:
        image = nibabel.load(path)
    except Exception:  # NRRD, which NiBabel does not read, or a file it cannot: the library says why
        return path
    if not isinstance(image, nibabel.Nifti1Image):
        return path
    try:
        data = np.asanyarray(image.dataobj)
    except Exception:  # a truncated or corrupt file: the library reads it and says why, as every call does
        from . import _core

        _core.TensorField.from_file(path, tensor_order=tensor_order, tensor_frame=tensor_frame)
        return path
    loaded = type(image)(data, image.affine, image.header)
    loaded.set_filename(path)  # messages name the file
    return loaded


def file_record(path):
    """The size and SHA-256 of a written file, as the statistics keep them."""
    digest = hashlib.sha256()
    with open_regular_binary(path) as file:
        for block in iter(lambda: file.read(1 << 20), b""):
            digest.update(block)
        size = file.tell()
    return {"bytes": size, "sha256": digest.hexdigest()}


class _SeedLabels:
    """A seed label image, read once per task: the seeds of one region as an
    image on the file's grid (the library checks it against the tensors'),
    read once its header is known to be on the grid of the tensor file
    ``tensors`` (the library's check, which reads no data: a small .nii.gz
    can declare billions of voxels)."""

    def __init__(self, path, tensors):
        import nibabel

        from . import _core

        self.path = path
        _core.require_image_on_grid(path, tensors, "the seed labels are")
        require_regular_file(path)
        try:
            image = nibabel.load(path)
            self.labels = np.asanyarray(image.dataobj)
        except Exception as error:
            # A truncated or corrupt file: the library's message, the one
            # stvd.propagate, the Nipype nodes and the tool give for it.
            _core.read_label_image(path, tensors, "the seed labels are")
            raise ValueError(f"{path}: cannot read the seed labels: {one_line(error)}") from None
        self.affine = image.affine

    def region(self, label):
        import nibabel

        image = nibabel.Nifti1Image((self.labels == label).astype(np.uint8), self.affine)
        image.set_filename(self.path)  # messages name the file; outputs are checked against it
        return image


def _round(value):
    return float(f"{float(value):.6g}")


def _map_summary(propagation, seeds):
    finite = propagation.distance[np.isfinite(propagation.distance)]
    if isinstance(seeds, dict):  # a region of a seed label image
        summary = {"label": seeds["label"], "seed_voxels": len(propagation.seeds),
                   "seed_voxels_left_out": int(propagation.label_seeds_left_out)}
    else:
        summary = {"seeds": [list(map(int, s)) for s in seeds]}
    return dict(summary, termination=propagation.termination, reached_voxels=int(finite.size),
                domain_voxels=int(propagation.voxel_counts["domain"]),
                median_mm=_round(np.median(finite)) if finite.size else None,
                max_mm=_round(finite.max()) if finite.size else None)


def _connectivity_summary(result):
    geodesic = result.geodesic_mm[np.isfinite(result.geodesic_mm)]
    n = len(result.labels)
    return {"regions": [int(v) for v in result.labels], "voxels": [int(v) for v in result.voxels],
            "labels_left_out": int(result.labels_left_out),  # regions without a voxel in the domain
            "pairs": n * (n - 1), "pairs_connected": int(geodesic.size),
            "mean_geodesic_mm": _round(geodesic.mean()) if geodesic.size else None}


def output_files(folder, parts, report=False):
    """The outputs of ``parts`` in ``folder`` (and with ``report`` the QC
    page): ``{file name: (role, path)}``."""
    files = {}
    for part in parts:
        name = CONNECTIVITY_FILE if part == CONNECTIVITY else map_file(part)
        role = "connectivity table" if part == CONNECTIVITY else f"distance map of seed set {part}"
        files[name] = (role, os.path.join(folder, name))
    if report:
        files[REPORT_FILE] = ("QC page", os.path.join(folder, REPORT_FILE))
    return files


def _write_report(out, path, subject, tensors, propagation, connectivity):
    """Stages the subject's QC page (``stvd.report``): the first distance map
    of the task over FA, with its seeds, and the connectivity heat maps."""
    from . import report

    def write(staging):
        report.write_report(staging, propagation, connectivity=connectivity,
                            labels=subject.labels if connectivity is not None else None,
                            tensors=tensors if propagation is None else None, subject=subject.id,
                            command_line="stvd cohort")

    out.write(path, write)


def compute_parts(subject, parts, seed_sets, folder, options, report=False):
    """Computes ``parts`` of ``subject`` (a ``_manifest.Subject``) and writes
    their outputs into ``folder``. ``seed_sets``: ``{name: [(i, j, k), ...]
    or {'label': value}}`` of the parts that are seed sets; ``options``: the
    keywords of the package's calls; ``report``: write the subject's QC page
    too (what this task computed). Returns ``{'parts': {part: summary},
    'outputs': {file: {'bytes', 'sha256'}}, 'run': {...}}``, or ``{'error':
    one line}`` for a subject that cannot be computed. Never raises for bad
    input: a bad subject must not stop the others."""
    import stvd

    start = time.perf_counter()
    files = output_files(folder, parts, report)
    try:
        tensor_options = {name: options.get(name) for name in (
            "tensor_kind", "diffusion_metric", "max_anisotropy", "fa_threshold")}
        method_options = {name: options.get(name) for name in ("method", "k", "chain_measure", "stencil")}
        common = dict(mask=subject.mask, tensor_order=subject.tensor_order, tensor_frame=subject.tensor_frame,
                      **tensor_options, **method_options)
        summaries = {}
        with stvd.OutputFiles(dict(files.values()), inputs=subject.input_roles()) as out:
            tensors = _load_tensors(subject.tensors, subject.tensor_order, subject.tensor_frame)
            seed_labels, first_map, table = None, None, None
            for part in parts:
                path = files[CONNECTIVITY_FILE if part == CONNECTIVITY else map_file(part)][1]
                if part == CONNECTIVITY:
                    result = stvd.connectivity(tensors, subject.labels, threads=options.get("threads"), **common)
                    out.write_text(path, connectivity_table(result))
                    summaries[part] = _connectivity_summary(result)
                    table = result
                    continue
                seeds = seed_sets[part]
                if isinstance(seeds, dict):
                    seed_labels = seed_labels or _SeedLabels(subject.seeds, subject.tensors)
                    try:
                        propagation = stvd.propagate(tensors, seed_labels=seed_labels.region(seeds["label"]),
                                                     max_distance=options.get("max_distance"), **common)
                    except ValueError as error:
                        raise ValueError(f"{one_line(error)} (seed region {seeds['label']})") from None
                else:
                    propagation = stvd.propagate(tensors, seeds, max_distance=options.get("max_distance"), **common)
                propagation.save(path, options.get("unreachable_value"), outputs=out)
                summaries[part] = _map_summary(propagation, seeds)
                if first_map is None:
                    first_map = propagation
            if report:
                _write_report(out, files[REPORT_FILE][1], subject, tensors, first_map, table)
        # The QC page says when it was made: its record goes with the run's
        # (where and when), not with the statistics (the same on any cluster).
        outputs = {name: file_record(path) for name, (_, path) in files.items() if name != REPORT_FILE}
        page = {"qc_page": file_record(files[REPORT_FILE][1])} if report else {}
    except (ValueError, TypeError, OSError, MemoryError, EOFError) as error:
        return {"error": one_line(error)}
    except Exception as error:  # anything else from reading a hostile file is still this subject's failure
        return {"error": f"{type(error).__name__}: {one_line(error)}"}
    return {"parts": summaries, "outputs": outputs,
            "run": {"seconds": round(time.perf_counter() - start, 3), "host": socket.gethostname(),
                    "pid": os.getpid(), **page,
                    # ru_maxrss is in KiB on Linux: the worker's peak so far.
                    "worker_peak_rss_mib": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)}}
