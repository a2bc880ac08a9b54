"""FOD images (fibre orientation distributions, docs/fod.md): the inputs
stvd.fod_distance takes (files, NiBabel images, arrays with an affine, DIPY's
spherical-harmonic fits) turned into what the extension module takes."""

import os

import numpy as np

from . import _core
from ._inputs import image_name, image_zooms, is_image, is_path, point_list, scalar_image_spec, voxel_list
from ._progress import progress_reporter

# DIPY's (basis_type, legacy) and stvd's name for the same functions
# (docs/fod.md, "The bases").
_DIPY_BASES = {("tournier07", False): "tournier07", ("tournier07", True): "tournier07_legacy",
               ("descoteaux07", False): "descoteaux07", ("descoteaux07", True): "descoteaux07_legacy"}


def is_dipy_fit(value):
    """Whether ``value`` is a spherical-harmonic fit of DIPY (SphHarmFit, which
    CSD's fit is): coefficients in ``shm_coeff`` and the model in ``model``."""
    return hasattr(value, "shm_coeff") and hasattr(value, "model") and not isinstance(value, np.ndarray)


def recorded_basis(fit):
    """The basis a DIPY fit records, as stvd names it, or None. DIPY 1.6's
    SphHarmFit, its models (ConstrainedSphericalDeconvModel, the Q-ball
    models) record no basis: they always fit DIPY's descoteaux07 functions
    with legacy=True, and nothing on the object says so. A model that
    records ``basis_type`` (and ``legacy``, True when absent, DIPY's
    default) is taken at its word."""
    model = fit.model
    basis_type = getattr(model, "basis_type", None)
    if not isinstance(basis_type, str):
        return None
    legacy = getattr(model, "legacy", True)
    name = _DIPY_BASES.get((basis_type, bool(legacy)))
    if name is None:
        raise ValueError(f"fod: the DIPY fit records basis_type={basis_type!r}, which stvd does not know")
    return name


def fod_arguments(fod, affine, fod_basis):
    """(coefficients, affine, zooms, name, path, basis) for the extension."""
    if fod is None:
        raise TypeError("fod: expected a path, a NiBabel image, a DIPY fit or an array, got None")
    if is_path(fod):
        if affine is not None:
            raise ValueError("affine= applies to arrays and DIPY fits; a file has its own geometry")
        return None, None, None, os.fspath(fod), os.fspath(fod), fod_basis
    if is_image(fod):
        if affine is not None:
            raise ValueError("affine= applies to arrays and DIPY fits; a NiBabel image has its own")
        return (np.asanyarray(fod.dataobj), fod.affine, image_zooms(fod), image_name(fod, "fod"), None, fod_basis)
    if is_dipy_fit(fod):
        recorded = recorded_basis(fod)
        if recorded is not None and fod_basis is not None and fod_basis != recorded:
            raise ValueError(f"fod_basis='{fod_basis}': the DIPY fit records its basis as '{recorded}'")
        if recorded is None and fod_basis is None:
            raise ValueError(
                "fod_basis: this DIPY fit does not record its basis (DIPY 1.6's fits do not: its CSD and "
                "SphHarmModel fits are in 'descoteaux07_legacy'); state it with fod_basis=")
        if affine is None:
            raise ValueError("fod: a DIPY fit has no affine; give affine=, the 4x4 matrix from voxel indices to RAS "
                             "millimetres of the data it was fitted to")
        return np.asarray(fod.shm_coeff), affine, None, "DIPY fit", None, fod_basis or recorded
    if affine is None:
        raise ValueError("fod: an array needs affine=, the 4x4 matrix from voxel indices to RAS millimetres")
    return fod, affine, None, "fod", None, fod_basis


def fod_distance_run(fod, seeds, seed_points, seed_labels, lps, affine, fod_basis, fod_frame, fod_floor, fod_power,
                     mask, method, k, steiner, stencil, domain_connectivity, max_distance, unreachable_value, threads, progress,
                     memory_check):
    """The extension's run, a dict: "distance" (float64, inf where not
    reached), "distance_map" (float32 as the tool writes it), "affine", the
    seeds and the figures of the run."""
    coefficients, affine, zooms, name, path, basis = fod_arguments(fod, affine, fod_basis)
    if threads is not None and (isinstance(threads, bool) or int(threads) != threads or threads < 0):
        raise ValueError(f"threads={threads!r}: expected a count of threads (0 or None: one per core)")
    with progress_reporter(progress) as reporter:
        run = _core.fod_distance(
            coefficients, affine, zooms, name, path, basis, fod_frame,
            None if fod_floor is None else float(fod_floor), None if fod_power is None else float(fod_power),
            scalar_image_spec(mask, "mask"), voxel_list(seeds, "seeds", "seed_points"),
            point_list(seed_points, "seed_points"), bool(lps), scalar_image_spec(seed_labels, "seed_labels"),
            method, k, steiner, stencil, None if domain_connectivity is None else str(domain_connectivity), max_distance,
            float(unreachable_value), int(threads or 0), reporter.callback, bool(memory_check))
        reporter.finish(run["finalized_vertices"])
    return run


def _threads_of(threads):
    if threads is not None and (isinstance(threads, bool) or int(threads) != threads or threads < 0):
        raise ValueError(f"threads={threads!r}: expected a count of threads (0 or None: one per core)")
    return int(threads or 0)


def _cost_of(fod_floor, fod_power):
    return (None if fod_floor is None else float(fod_floor), None if fod_power is None else float(fod_power))


def fod_paths_run(fod, seeds, targets, seed_points, seed_labels, target_points, target_labels, lps, affine, fod_basis,
                  fod_frame, fod_floor, fod_power, mask, method, stencil, domain_connectivity, threads, progress,
                  memory_check):
    """The extension's run of stvd.fod_paths, a dict: "paths" (one record
    per target, as stvd.Paths takes them), "grid" (which writes them), the
    grid's affine, shape, zooms and axis codes, and the metric's figures."""
    coefficients, affine, zooms, name, path, basis = fod_arguments(fod, affine, fod_basis)
    floor, power = _cost_of(fod_floor, fod_power)
    with progress_reporter(progress) as reporter:
        run = _core.fod_paths(
            coefficients, affine, zooms, name, path, basis, fod_frame, floor, power, scalar_image_spec(mask, "mask"),
            voxel_list(seeds, "seeds", "seed_points"), point_list(seed_points, "seed_points"), bool(lps),
            scalar_image_spec(seed_labels, "seed_labels"), voxel_list(targets, "targets", "target_points"),
            point_list(target_points, "target_points"), scalar_image_spec(target_labels, "target_labels"), method,
            stencil, None if domain_connectivity is None else str(domain_connectivity), _threads_of(threads),
            reporter.callback, bool(memory_check))
    return run


def fod_connectivity_run(fod, labels, affine, fod_basis, fod_frame, fod_floor, fod_power, mask, method, stencil,
                         domain_connectivity, threads, progress, memory_check):
    """The extension's run of stvd.fod_connectivity: the dict
    stvd.Connectivity takes, with the metric's figures."""
    coefficients, affine, zooms, name, path, basis = fod_arguments(fod, affine, fod_basis)
    floor, power = _cost_of(fod_floor, fod_power)
    with progress_reporter(progress) as reporter:
        return _core.fod_connectivity(
            coefficients, affine, zooms, name, path, basis, fod_frame, floor, power, scalar_image_spec(mask, "mask"),
            scalar_image_spec(labels, "labels"), method, stencil,
            None if domain_connectivity is None else str(domain_connectivity), _threads_of(threads),
            reporter.callback, bool(memory_check))


class FodPathsSource:
    """What stvd.Paths.save writes FOD paths with (the grid of the run): the
    place a stvd.Propagation holds for tensor paths."""

    def __init__(self, grid):
        self._result = grid


# ---------------------------------------------------------------------------
# The record of a run, for its QC page (stvd.report.write_report)


class FodRun:
    """What an FOD run from Python keeps for its QC page
    (``stvd.report.write_report``), as the tool's page of the same run reads
    it from the run's files: ``statistics``, the parts of the tool's
    ``--stats`` record a page shows (the metric's parameters by the same
    names: basis as resolved and as given, frame, lmax, floor, power,
    sampling directions, the norm; the method, the seeds, the domain), the
    grid (``affine``, ``shape``), ``distance`` (float64, NaN where not
    reached; None for connectivity), ``seeds`` (voxel indices), ``gfa`` (the
    FOD's generalised fractional anisotropy, the page's background) and
    ``mask`` (as it was given). Held by the image ``stvd.fod_distance``
    returns (``image.extra["stvd_fod_run"]``), and as ``fod_run`` by the
    ``stvd.Paths`` of ``stvd.fod_paths`` and the ``stvd.Connectivity`` of
    ``stvd.fod_connectivity``."""

    def __init__(self, statistics, affine, shape, distance, seeds, gfa, mask, input_file):
        self.statistics = statistics
        self.input_file = input_file  # the FOD's file, None for an array or a DIPY fit
        self.affine = np.asarray(affine, dtype=np.float64)
        self.shape = tuple(int(n) for n in shape)
        self.distance = distance
        self.seeds = np.asarray(seeds, dtype=np.int64).reshape(-1, 3)
        self.gfa = gfa
        self.mask = mask

    def __repr__(self):
        return f"<stvd FOD run: {self.statistics.get('command')} on {self.statistics.get('input')}>"


def _name_of(value):
    """How the tool's statistics name an input: its path as given ("" for
    none); for what Python alone takes, the file it was loaded from or what
    it is."""
    if value is None:
        return ""
    if is_path(value):
        return os.fspath(value)
    if is_image(value):
        return value.get_filename() or "a NiBabel image"
    return "an array"


def fod_run_record(run, command, fod, affine, fod_basis, fod_frame, mask, seed_labels=None, labels=None,
                   target_labels=None, unreachable_value=None):
    """The FodRun of an extension's run dict (fod_distance, fod_paths or
    fod_connectivity) made by the call with these arguments."""
    _, _, _, name, path, basis = fod_arguments(fod, affine, fod_basis)
    parameters = {"method": run["method"], "stencil": run["stencil"], "metric": "fod",
                  "fod_basis": run["fod_basis"], "fod_basis_given": basis, "fod_frame": run["fod_frame"],
                  "fod_frame_stated": fod_frame is not None, "fod_lmax": int(run["fod_lmax"]),
                  "fod_floor": float(run["fod_floor"]), "fod_power": float(run["fod_power"]),
                  "fod_directions": int(run["fod_directions"]), "fod_norm": run["fod_norm"], "mask": _name_of(mask)}
    for key, value in (("labels", labels), ("target_labels", target_labels)):
        if value is not None:
            parameters[key] = _name_of(value)
    if command != "connectivity":
        parameters["seed_labels"] = _name_of(seed_labels)
    if unreachable_value is not None:
        parameters["unreachable_value"] = float(unreachable_value)
    from . import __version__

    shape = tuple(int(n) for n in run["shape"]) if "shape" in run else None
    total = int(np.prod(shape)) if shape else None
    domain = int(run["domain_voxels"])
    statistics = {"command": command, "stvd_version": __version__, "input": path or name,
                  "parameters": parameters, "voxels": {"total": total, "domain": domain}}
    seeds = np.zeros((0, 3), np.int64)
    distance = None
    if "seeds" in run:
        seeds = np.asarray(run["seeds"], dtype=np.int64).reshape(-1, 3)
        ras = np.asarray(run["affine"], np.float64) @ np.c_[seeds[:100], np.ones(len(seeds[:100]))].T
        statistics["seeds"] = [{"voxel": [int(c) for c in seed], "ras_mm": [float(x) for x in point]}
                               for seed, point in zip(seeds[:100], ras[:3].T)]
        statistics["seed_count"] = int(len(seeds))
        statistics["label_seeds_left_out"] = int(run["label_seeds_left_out"])
    if "distance" in run:
        distance = np.where(np.isfinite(run["distance"]), run["distance"], np.nan)
        statistics["propagation"] = {"vertices": total, "domain_vertices": domain,
                                     "finalized_vertices": int(run["finalized_vertices"]),
                                     "termination": run["termination"]}
        finite = distance[np.isfinite(distance)]
        if finite.size:
            statistics["distance_mm"] = {"reached": int(finite.size), "min": float(finite.min()),
                                         "median": float(np.median(finite)), "max": float(finite.max())}
    statistics["fod_precomputation"] = {"seconds": float(run["table_seconds"]), "threads": int(run["table_threads"]),
                                        "voxels": domain}
    return FodRun(statistics, run["affine"], shape, distance, seeds, run["gfa"], mask,
                  path or (image_name(fod, None) if is_image(fod) else None))
