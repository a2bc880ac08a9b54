"""stvd: anisotropic geodesic distances, paths and connectivity on diffusion
tensor images, tetrahedral meshes and surfaces.

A thin layer over stvd's C++ library (the ``stvd`` command-line tool runs the
same code): NumPy arrays and NiBabel images in, distances, paths and
connectivity out. Every option that is not given takes the library's default
(``stvd.defaults``); option names follow the tool's flags (``--seed-point``
is ``seed_points=``, ``--tensor-order`` is ``tensor_order=``), and bad input
raises ValueError or TypeError with the tool's one-line messages, which name
options by these keywords (``k must be between 1 and 16``). The library
works without the GIL, so threads run in parallel. See docs/python.md.
"""

import os

import numpy as np

from . import _core
from ._fod import FodPathsSource, fod_connectivity_run, fod_distance_run, fod_paths_run, fod_run_record
from ._inputs import index_list, is_image, is_path, point_list, scalar_image_spec, tensor_field, voxel_list
from ._outputs import FileConflictError, OutputError, OutputFiles, input_file_of
from ._paths import Paths, tractogram
from ._progress import progress_reporter
from ._regions import long_table, read_label_names, region_names, square_table

__version__ = _core.__version__
NO_VERTEX = _core.NO_VERTEX

__all__ = ["defaults", "distance", "fod_distance", "fod_paths", "fod_connectivity", "propagate", "Propagation", "trace_paths", "Paths",
           "tractogram", "connectivity", "Connectivity", "read_label_names", "check_tensor_frame",
           "tet_mesh_distance", "surface_distance", "NO_VERTEX", "OutputFiles", "FileConflictError", "OutputError",
           "read_surface", "read_surface_values", "read_surface_regions", "region_vertices", "write_surface_values",
           "surface_region_distances", "SurfaceSolver"]


class _Defaults:
    """The library's defaults, read-only: ``stvd.defaults.k``, ...

    method, k (on volumes), surface_k, tet_mesh_k (the k of each kind of
    domain when none is given), chain_measure, surface_chain_measure (the
    same measure), stencil, domain_connectivity (volumes), tensor_kind,
    diffusion_metric, max_anisotropy (None: diffusion tensors capped at
    diffusion_max_anisotropy, a metric taken as given),
    accept_implausible_tensors, accept_misaligned_tensors, memory_check, lps,
    unreachable_value,
    metric (surfaces), step, smooth, refine, discrete (paths), max_k,
    max_steiner. The values are the library's option declarations, the ones
    the ``stvd`` tool parses and prints its help with
    (``stvd._core.option_declarations()``).
    """

    def __init__(self, values):
        object.__setattr__(self, "_values", dict(values))

    def __getattr__(self, name):
        try:
            return self._values[name]
        except KeyError:
            raise AttributeError(name) from None

    def __setattr__(self, name, value):
        raise AttributeError("stvd.defaults is read-only: pass the option to the call instead")

    def __dir__(self):
        return list(self._values)

    def __repr__(self):
        return "stvd.defaults(" + ", ".join(f"{k}={v!r}" for k, v in self._values.items()) + ")"

    def as_dict(self):
        return dict(self._values)


defaults = _Defaults(_core.defaults())


def _connectivity(value):
    """domain_connectivity (6, 18 or 26, or the same as text) as the tool's
    option text, which the library checks; None kept."""
    return None if value is None else str(value)


def _tensor_options(tensor_order, tensor_frame, tensor_kind, diffusion_metric, max_anisotropy, fa_threshold,
                    accept_implausible_tensors=False, accept_misaligned_tensors=False):
    return dict(tensor_order=tensor_order, tensor_frame=tensor_frame, tensor_kind=tensor_kind,
                diffusion_metric=diffusion_metric, max_anisotropy=max_anisotropy, fa_threshold=fa_threshold,
                accept_implausible_tensors=bool(accept_implausible_tensors),
                accept_misaligned_tensors=bool(accept_misaligned_tensors))


class Propagation:
    """A finished propagation over a tensor volume (``stvd.propagate``).

    ``distance`` (float64 millimetres, ``inf`` where not reached) and
    ``predecessor`` (uint32 linear voxel index ``i + nx*(j + ny*k)`` of each
    voxel's predecessor: the voxel its distance was measured from, the start
    of the straight segment that gave it with STVD's default segment measure,
    not necessarily a neighbour; ``stvd.NO_VERTEX`` for seeds and voxels not
    reached)
    are read-only arrays on the input's grid, without a copy. Statistics:
    ``termination``, ``finalized_vertices``, ``relaxed_edges``,
    ``peak_state_bytes``, ``seeds`` (the seed voxels), ``label_seeds_left_out``,
    ``voxel_counts``, ``method``, ``k``, ``chain_measure``, ``stencil``,
    ``domain_connectivity``. The
    grid: ``shape``, ``affine`` (voxel index to RAS millimetres), ``zooms``,
    ``in_domain``. Paths (``stvd.trace_paths``) and connectivity
    (``stvd.connectivity``) use it without propagating again.
    ``input_files``: (role, path) of the files it read (tensors, mask, seed
    labels; NiBabel images by the files they came from), which ``save``
    never writes over.
    """

    def __init__(self, result, template, input_files=()):
        self._result = result
        self._template = template
        self.input_files = [(role, path) for role, path in input_files if path]

    def __getattr__(self, name):
        if name in ("distance", "predecessor", "termination", "finalized_vertices", "relaxed_edges",
                    "peak_state_bytes", "seeds", "label_seeds_left_out", "method", "method_text", "k",
                    "chain_measure", "stencil", "domain_connectivity"):
            return getattr(self._result, name)
        if name in ("shape", "affine", "zooms", "voxel_counts", "in_domain", "fractional_anisotropy", "tensor_info"):
            return getattr(self._result.field, name)
        raise AttributeError(name)

    def distance_map(self, unreachable_value=None):
        """The distance map as ``stvd distance`` writes it: float32, voxels not
        reached holding ``unreachable_value`` (``stvd.defaults.unreachable_value``
        when None). A NiBabel image whenever an affine is known: an image or
        a file came in (its affine and header), or an array with ``affine=``
        (that affine); so ``nibabel.save`` takes it. A NumPy array only when
        NiBabel is not installed. ``np.asanyarray(image.dataobj)`` is the
        array."""
        if unreachable_value is None:
            unreachable_value = defaults.unreachable_value
        data = self._result.distance_map(float(unreachable_value))
        return self._template(data) if self._template else data

    def save(self, path, unreachable_value=None, *, outputs=None):
        """Writes the distance map to ``path`` (NIfTI, NRRD or MRtrix by the
        extension) as ``stvd distance -o path`` writes it, byte for byte, with
        the tool's promises: never over one of ``input_files``, atomically.
        Within ``outputs`` (a ``stvd.OutputFiles`` that declares ``path`` and
        these input files) it is staged there and appears at its commit."""
        if unreachable_value is None:
            unreachable_value = defaults.unreachable_value
        if outputs is None:
            with OutputFiles({"distance map": path}, inputs=self.input_files) as files:
                self.save(path, unreachable_value, outputs=files)
            return
        outputs._require_inputs(self.input_files, "the propagation")
        self._result.write_distance_map(outputs._transaction, outputs._declared_output(path),
                                        float(unreachable_value))

    def __repr__(self):
        return (f"<stvd.Propagation {self.method_text} on {self.shape}: {self.finalized_vertices} of "
                f"{self.voxel_counts['domain']} domain voxels reached, {self.termination}>")


def _image_template(tensors, field, affine=None):
    """How to wrap a distance map in an image of the input's grid, or None
    when no affine is known (or NiBabel is missing). An array given with
    ``affine=`` gets a NIfTI image with that affine, as given."""
    try:
        import nibabel
    except ImportError:
        return None

    if is_image(tensors):
        nifti = isinstance(tensors, nibabel.Nifti1Image)  # NIfTI-2 images are NIfTI-1 images too
        header = tensors.header.copy() if nifti else None
        image_class = type(tensors) if nifti else nibabel.Nifti1Image
        affine = tensors.affine
    elif is_path(tensors):
        try:  # a NIfTI file keeps its own header (read lazily, without the data)
            source = nibabel.load(tensors)
            nifti = isinstance(source, nibabel.Nifti1Image)
            header = source.header.copy() if nifti else None
            image_class = type(source) if nifti else nibabel.Nifti1Image
            affine = source.affine if nifti else field.affine
        except Exception:  # NRRD, which NiBabel does not read
            header, affine, image_class = None, field.affine, nibabel.Nifti1Image
    elif affine is not None:
        # The affine as given: the header stores it in single precision, the
        # image keeps the caller's matrix.
        return _ImageTemplate(None, affine, nibabel.Nifti1Image, exact_affine=True)
    else:
        return None

    return _ImageTemplate(header, affine, image_class)


class _ImageTemplate:
    """Wraps a distance map in a NIfTI image of the input's grid: the input's
    header (NIfTI inputs) or a new one, and its affine. A class, not a
    closure, so that a Propagation pickles with it."""

    def __init__(self, header, affine, image_class, exact_affine=False):
        self.header, self.affine, self.image_class = header, np.array(affine, dtype=np.float64), image_class
        self.exact_affine = exact_affine

    def __call__(self, data):
        import nibabel

        if self.header is None:
            image = nibabel.Nifti1Image(data, self.affine)
            image.set_qform(self.affine, code=1, update_affine=not self.exact_affine)
            image.set_sform(self.affine, code=1, update_affine=not self.exact_affine)
            return image
        out = self.header.copy()
        out.set_intent("none", (), name="")
        out.set_data_dtype(np.float32)
        out.set_slope_inter(None, None)
        return self.image_class(data, self.affine, out)


def propagate(tensors, seeds=None, *, affine=None, seed_points=None, seed_labels=None, lps=False, mask=None,
              tensor_order=None, tensor_frame=None, tensor_kind=None, diffusion_metric=None, max_anisotropy=None,
              fa_threshold=None, method=None, k=None, chain_measure=None, stencil=None, steiner=None,
              max_distance=None, progress=None, accept_implausible_tensors=False, accept_misaligned_tensors=False,
              domain_connectivity=None, memory_check=True):
    """Propagates the geodesic distance from seeds over a tensor volume and
    returns the whole result (``stvd.Propagation``): distances, predecessors
    and statistics. The arguments are those of ``stvd.distance``."""
    field = tensor_field(tensors, affine, mask, _tensor_options(tensor_order, tensor_frame, tensor_kind,
                                                                diffusion_metric, max_anisotropy, fa_threshold,
                                                                accept_implausible_tensors,
                                                                accept_misaligned_tensors))
    labels = scalar_image_spec(seed_labels, "seed_labels")
    with progress_reporter(progress) as reporter:
        result = field.propagate(voxel_list(seeds, "seeds", "seed_points"), point_list(seed_points, "seed_points"), bool(lps),
                                 labels, method=method, k=k, chain_measure=chain_measure, stencil=stencil,
                                 steiner=steiner, max_distance=max_distance, progress=reporter.callback,
                                 domain_connectivity=_connectivity(domain_connectivity),
                                 memory_check=bool(memory_check))
        reporter.finish(result.finalized_vertices)
    template = _image_template(tensors, field, affine)
    return Propagation(result, template,
                       [("tensor input", input_file_of(tensors)), ("mask", input_file_of(mask)),
                        ("seed labels", input_file_of(seed_labels))])


def distance(tensors, seeds=None, *, affine=None, seed_points=None, seed_labels=None, lps=False, mask=None,
             tensor_order=None, tensor_frame=None, tensor_kind=None, diffusion_metric=None, max_anisotropy=None,
             fa_threshold=None, method=None, k=None, chain_measure=None, stencil=None, steiner=None,
             max_distance=None, unreachable_value=None, progress=None, accept_implausible_tensors=False,
             accept_misaligned_tensors=False, domain_connectivity=None, memory_check=True):
    """The anisotropic geodesic distance (millimetres) from seeds over a
    diffusion or metric tensor volume, as ``stvd distance`` computes it.

    tensors: a path (NIfTI or NRRD, read as the tool reads it), a NiBabel
        image (read as the tool reads its file), or a NumPy array with
        ``affine=`` (4x4, voxel index to RAS millimetres): ``(X, Y, Z, 6)`` in
        the order ``tensor_order=`` states (``'lower'``, ``'fsl'`` or
        ``'mrtrix'``), or ``(X, Y, Z, 3, 3)`` as DIPY's
        ``TensorFit.quadratic_form``. float32 or float64.
    seeds: voxel indices ``(i, j, k)``, 0-based, integers (float seeds are
        refused: DIPY's are millimetres); ``seed_points=``: world
        millimetres, RAS+ (the frame of the image's affine, of
        nibabel.streamlines and of DIPY's ``seeds_from_mask``; LPS with
        ``lps=True``), the nearest voxel;
        ``seed_labels=``: every non-zero voxel of a label image (path, image
        or array on the tensors' grid) inside the domain.
    mask, fa_threshold, tensor_frame, tensor_kind, diffusion_metric,
        max_anisotropy, accept_implausible_tensors, accept_misaligned_tensors:
        the domain and the metric, as the tool's options (diffusion tensors
        whose principal directions follow the tracts clearly better with
        their components flipped or permuted along the image axes raise
        ValueError unless ``accept_misaligned_tensors``; see
        ``stvd.check_tensor_frame``).
    method, k, chain_measure, stencil, steiner, max_distance,
        domain_connectivity: the propagation, as the tool's options
        (``domain_connectivity`` 6, 18 or 26: which domain voxels touch when
        a mask or an FA threshold leaves gaps; paths keep to it too).
    unreachable_value: the value of voxels not reached.
    progress: True for a tqdm bar, or a function
        ``f(finalized, domain_vertices, front_mm)``; returning False cancels.
    memory_check: a run that would not fit into the memory available (the
        system's, the control group's, ``ulimit -v``) raises MemoryError
        before it starts; False runs it anyway (the tool's
        ``--no-memory-check``).

    Options left at None take ``stvd.defaults``. Returns the float32 distance
    map on the input's grid as a NiBabel image with the input's affine (an
    image's or a file's affine and header, or the ``affine=`` given with an
    array); a NumPy array only when NiBabel is not installed.
    """
    result = propagate(tensors, seeds, affine=affine, seed_points=seed_points, seed_labels=seed_labels, lps=lps,
                       mask=mask, tensor_order=tensor_order, tensor_frame=tensor_frame, tensor_kind=tensor_kind,
                       diffusion_metric=diffusion_metric, max_anisotropy=max_anisotropy, fa_threshold=fa_threshold,
                       method=method, k=k, chain_measure=chain_measure, stencil=stencil, steiner=steiner,
                       max_distance=max_distance, progress=progress,
                       accept_implausible_tensors=accept_implausible_tensors,
                       accept_misaligned_tensors=accept_misaligned_tensors,
                       domain_connectivity=domain_connectivity, memory_check=memory_check)
    return result.distance_map(unreachable_value)


class _GridOf:
    """The grid of a run, for _image_template (an MRtrix file's affine)."""

    def __init__(self, affine):
        self.affine = affine


def fod_distance(fod, seeds=None, *, fod_basis=None, affine=None, seed_points=None, seed_labels=None, lps=False,
                 mask=None, fod_frame=None, fod_floor=None, fod_power=None, method=None, k=None, steiner=None,
                 stencil=None,
                 domain_connectivity=None, max_distance=None, unreachable_value=None, threads=None, progress=None,
                 memory_check=True):
    """The geodesic distance (millimetres) from seeds under the metric of a
    fibre orientation distribution (FOD) image, as ``stvd distance FOD
    --fod-basis NAME`` computes it: STVD (or ``method=``) over the voxel
    grid with the convexified FOD norm F* (docs/fod.md), the same map, bit
    for bit.

    fod: spherical-harmonic coefficients per voxel: a path (``.mif``,
        ``.mif.gz``, ``.mih``, ``.nii``, ``.nii.gz``: X, Y, Z, N), a NiBabel
        image, a NumPy array ``(X, Y, Z, N)`` with
        ``affine=`` (4x4, voxel index to RAS millimetres), or a DIPY
        spherical-harmonic fit (``SphHarmFit``, what
        ``ConstrainedSphericalDeconvModel.fit`` returns: its ``shm_coeff``,
        with ``affine=`` of the data it was fitted to). N is 15, 28, 45, 66
        or 91 (lmax 4 to 12).
    fod_basis: required (an FOD's coefficients do not say their basis):
        ``'mrtrix3'`` (MRtrix3's dwi2fod, scanner frame), ``'tournier07'``,
        ``'tournier07_legacy'``, ``'descoteaux07'``,
        ``'descoteaux07_legacy'`` (DIPY's names; DIPY 1.6's CSD fits are
        ``'descoteaux07_legacy'``, and its fit objects do not record it, so
        it is required for them too).
    fod_frame: ``'scanner'`` or ``'voxel'``; unset: scanner for .mif files and
        ``'mrtrix3'``, voxel (DIPY's) for DIPY's names.
    fod_floor, fod_power: the cost (docs/fod.md, "The cost").
    seeds, seed_points, seed_labels, lps, mask, stencil (6, 18 or 26),
        domain_connectivity, max_distance, unreachable_value, progress,
        memory_check: as for ``stvd.distance``.
    method: ``'stvd'`` (the default, as in the tool and for tensors;
        ``k=``, 6 when unset), ``'dijkstra'`` or ``'lanthier'``
        (``steiner=`` M, required), as for ``stvd.distance``: STVD and
        Lanthier measure segments by F* tabulated along the lattice of order
        2, a table 1.2 times the cost of Dijkstra's along the 26 neighbour
        directions, for errors 2.6 to 2.8 times smaller in the mean
        (docs/fod.md, "STVD and Lanthier").
    threads: threads of the per-voxel table of F* (None or 0: one per core);
        the map is the same for any count.

    Returns the float32 distance map on the FOD's grid as a NiBabel image with
    the input's affine (a NumPy array when NiBabel is not installed), voxels
    not reached holding ``unreachable_value``; the image keeps the run's
    record for its QC page in ``extra["stvd_fod_run"]``
    (``stvd.report.write_report(output, image)``).
    """
    if unreachable_value is None:
        unreachable_value = defaults.unreachable_value
    run = fod_distance_run(fod, seeds, seed_points, seed_labels, lps, affine, fod_basis, fod_frame, fod_floor,
                           fod_power, mask, method, k, steiner, stencil, domain_connectivity, max_distance, unreachable_value,
                           threads, progress, memory_check)
    template = _image_template(fod, _GridOf(run["affine"]), affine)
    if not template:
        return run["distance_map"]
    image = template(run["distance_map"])
    # What its QC page shows (stvd.report.write_report(output, image)).
    image.extra["stvd_fod_run"] = fod_run_record(run, "distance", fod, affine, fod_basis, fod_frame, mask,
                                                 seed_labels=seed_labels, unreachable_value=unreachable_value)
    return image


def fod_paths(fod, seeds=None, targets=None, *, fod_basis=None, affine=None, seed_points=None, seed_labels=None,
              target_points=None, target_labels=None, lps=False, mask=None, fod_frame=None, fod_floor=None,
              fod_power=None, method=None, stencil=None, domain_connectivity=None, threads=None, progress=None,
              memory_check=True):
    """Geodesic paths from targets back to the seeds under the metric of an
    FOD image, as ``stvd path FOD --fod-basis NAME`` computes them: Dijkstra
    under the convexified FOD norm F*, and for each target the propagation's
    discrete path (voxel centres), whose F*-length is its ``geodesic_mm``
    (docs/fod.md, "Paths and connectivity"). No gradient descent or
    refinement: they would report a polyline whose F*-length is not the
    length reported.

    fod, fod_basis, affine, fod_frame, fod_floor, fod_power, seeds,
        seed_points, seed_labels, lps, mask, stencil, domain_connectivity,
        threads, progress, memory_check: as for ``stvd.fod_distance``.
    targets, target_points, target_labels: as for ``stvd.trace_paths``
        (voxel indices, RAS millimetres, one path per label).
    method: ``'dijkstra'`` only (the default here).

    Returns ``stvd.Paths`` (``metric_length_mm`` the polyline's F*-length,
    ``mean_fa`` NaN); ``save`` writes the tool's file, byte for byte;
    ``fod_run`` keeps the run's record for its QC page
    (``stvd.report.write_report(output, paths=paths)``).
    """
    run = fod_paths_run(fod, seeds, targets, seed_points, seed_labels, target_points, target_labels, lps, affine,
                        fod_basis, fod_frame, fod_floor, fod_power, mask, method, stencil, domain_connectivity,
                        threads, progress, memory_check)
    inputs = [("FOD input", input_file_of(fod)), ("mask", input_file_of(mask)),
              ("seed labels", input_file_of(seed_labels)), ("target labels", input_file_of(target_labels))]
    paths = Paths(run["paths"], run["affine"], run["shape"], run["zooms"], run["axis_codes"],
                  FodPathsSource(run["grid"]), inputs)
    paths.fod_run = fod_run_record(run, "path", fod, affine, fod_basis, fod_frame, mask, seed_labels=seed_labels,
                                   target_labels=target_labels)
    return paths


def fod_connectivity(fod, labels, *, fod_basis=None, affine=None, label_names=None, mask=None, fod_frame=None,
                     fod_floor=None, fod_power=None, method=None, stencil=None, domain_connectivity=None,
                     threads=None, progress=None, memory_check=True):
    """Region-to-region connectivity under the metric of an FOD image, as
    ``stvd connectivity FOD --fod-basis NAME`` computes it: one Dijkstra
    propagation under F* from each region of ``labels`` (a path, image or
    array on the FOD's grid), the path of each pair the discrete one
    (docs/fod.md, "Paths and connectivity"). ``threads``: the table of F*
    and the regions at once (None: one per core; the result does not
    depend on it). The other keywords as for ``stvd.fod_distance`` and
    ``stvd.connectivity``. Returns ``stvd.Connectivity``, with the metric's
    figures in ``fod_basis``, ``fod_frame``, ``fod_lmax``, ``fod_floor``,
    ``fod_power``, and the run's record for its QC page in ``fod_run``
    (``stvd.report.write_report(output, connectivity=result, labels=labels)``)."""
    names = read_label_names(label_names)
    values = fod_connectivity_run(fod, labels, affine, fod_basis, fod_frame, fod_floor, fod_power, mask, method,
                                  stencil, domain_connectivity, threads, progress, memory_check)
    record = fod_run_record(values, "connectivity", fod, affine, fod_basis, fod_frame, mask, labels=labels)
    for key in ("gfa", "affine", "shape"):  # kept by the record, for the page
        values.pop(key, None)
    result = Connectivity(values, names)
    result.fod_run = record
    return result


def trace_paths(result, targets=None, *, target_points=None, target_labels=None, lps=False, step=None, smooth=None,
                refine=None, discrete=False):
    """The geodesic paths from targets back to the seeds of a propagation, as
    ``stvd path`` traces them (``step``, ``smooth``, ``refine=False`` for
    ``--no-refine``, ``discrete=True`` for ``--discrete``). Targets: voxel
    indices, ``target_points=`` (RAS millimetres, LPS with ``lps=True``) or
    ``target_labels=`` (one path per label, to the region's voxel nearest to
    the seeds). Returns ``stvd.Paths``."""
    if not isinstance(result, Propagation):
        raise TypeError("result: expected the stvd.Propagation that stvd.propagate returns")
    labels = scalar_image_spec(target_labels, "target_labels")
    records = result._result.trace_paths(voxel_list(targets, "targets", "target_points"), point_list(target_points, "target_points"),
                                         bool(lps), labels, step=step, smooth=smooth, refine=refine,
                                         discrete=bool(discrete))
    field = result._result.field
    return Paths(records, field.affine, field.shape, field.zooms, field.axis_codes, result,
                 result.input_files + [("target labels", input_file_of(target_labels))])


class Connectivity:
    """Geodesic distance and connectivity between labelled regions
    (``stvd.connectivity``): ``labels`` (the regions' label values), ``voxels``
    (their voxels in the domain), and n x n matrices with row a measured from
    region a: ``geodesic_mm`` (d(a, b)), ``path_mm`` (Euclidean length of the
    path), ``straight_mm`` and ``connectivity`` (path_mm / geodesic_mm, the
    measure of Astola, Florack and ter Haar Romeny). NaN on the diagonal and
    where b is not reachable from a: the missing value of every
    connectivity output (``n/a`` in the tool's table, ``nan`` in its
    matrices). ``names``: each region's name from ``label_names=`` (the
    label value as text where it has none). ``labels_left_out``: regions
    without a voxel in the domain; ``threads``: how many ran;
    ``tensor_info`` and ``voxel_counts``: how the tensors were read and the
    domain, as on a ``stvd.Propagation``.

    With pandas: ``to_dataframe()`` gives the long table (one row per
    ordered pair, as ``stvd connectivity`` writes it, with the names),
    ``to_dataframe('square', measure='geodesic_mm')`` the matrix of one
    measure with rows and columns by region name."""

    def __init__(self, values, names=None):
        for key, value in values.items():
            setattr(self, key, value)
        if not hasattr(self, "names"):
            self.names = region_names(self.labels, names or {})

    def to_dataframe(self, form="long", measure="geodesic_mm"):
        """A pandas DataFrame: ``form='long'`` (region_a, region_b, name_a,
        name_b, geodesic_mm, path_mm, straight_mm, connectivity, voxels_a,
        voxels_b; one row per ordered pair a != b) or ``'square'`` (the n x n
        matrix of ``measure``, indexed by region name). NaN where there is no
        value. Needs pandas (Debian: python3-pandas)."""
        if form == "long":
            return long_table(self)
        if form == "square":
            return square_table(self, measure)
        raise ValueError(f"form: '{form}' is not one of long, square")

    def __repr__(self):
        return f"<stvd.Connectivity of {len(self.labels)} regions>"


def connectivity(tensors, labels, *, label_names=None, threads=None, affine=None, mask=None, tensor_order=None,
                 tensor_frame=None, tensor_kind=None, diffusion_metric=None, max_anisotropy=None, fa_threshold=None,
                 method=None, k=None, chain_measure=None, stencil=None, progress=None,
                 accept_implausible_tensors=False, accept_misaligned_tensors=False, domain_connectivity=None,
                 memory_check=True):
    """Region-to-region connectivity as ``stvd connectivity`` computes it: one
    propagation from each region of ``labels`` (a path, image or array on the
    tensors' grid; each distinct non-zero integer is a region), ``threads`` at
    a time (None: one per core; the result does not depend on it).
    ``tensors`` is what ``stvd.distance`` takes, or a ``stvd.Propagation``,
    whose field and method are reused; ``memory_check`` as there (the
    ``threads`` propagations at once must fit). ``label_names``: the
    regions' names, a label lookup file (a BIDS ``dseg.tsv`` table with
    ``index`` and ``name`` columns, or a FreeSurfer colour lookup table) or
    a dict ``{label: name}``. ``progress`` as for ``stvd.distance``, heard
    by every region's propagation; when it returns False (or on Ctrl-C) no
    table is returned: RuntimeError (KeyboardInterrupt) is raised. Returns
    ``stvd.Connectivity``."""
    names = read_label_names(label_names)
    if isinstance(tensors, Propagation):
        if accept_implausible_tensors or accept_misaligned_tensors or any(
                v is not None for v in (affine, mask, tensor_order, tensor_frame, tensor_kind, diffusion_metric,
                                        max_anisotropy, fa_threshold, method, k, chain_measure, stencil,
                                        domain_connectivity)):
            raise ValueError("tensor and method options come from the stvd.Propagation given")
        field = tensors._result.field
        given = tensors._result
        options = dict(method=given.method, k=given.k if given.method == "stvd" else None,
                       chain_measure=given.chain_measure if given.method == "stvd" else None, stencil=given.stencil,
                       domain_connectivity=str(given.domain_connectivity))
    else:
        field = tensor_field(tensors, affine, mask, _tensor_options(tensor_order, tensor_frame, tensor_kind,
                                                                    diffusion_metric, max_anisotropy, fa_threshold,
                                                                    accept_implausible_tensors,
                                                                    accept_misaligned_tensors))
        options = dict(method=method, k=k, chain_measure=chain_measure, stencil=stencil,
                       domain_connectivity=_connectivity(domain_connectivity))
    spec = scalar_image_spec(labels, "labels")
    with progress_reporter(progress) as reporter:
        values = field.connectivity(spec, threads=threads, progress=reporter.callback,
                                    memory_check=bool(memory_check), **options)
    # How the tensors were given and read, and the domain: what a QC page of
    # this result states (stvd.report.write_report).
    values["tensor_info"] = dict(field.tensor_info)
    values["voxel_counts"] = dict(field.voxel_counts)
    return Connectivity(values, names)


def check_tensor_frame(tensors, *, affine=None, mask=None, tensor_order=None, tensor_frame=None):
    """Whether the tensors' components are in the frame of the image axes, as
    ``stvd info`` checks it and every run of diffusion tensors does before
    it starts: deterministic streamlines of the principal eigenvector from
    the same high-FA voxels, under each of the 24 distinguishable flips and
    permutations of the components along the voxel axes i, j, k; the frame
    as read should give the longest ones. ``tensors``, ``affine``, ``mask``,
    ``tensor_order`` and ``tensor_frame`` as for ``stvd.distance``.

    Returns a dict: ``verdict`` ('consistent', 'mismatch' or
    'inconclusive'), ``summary`` (one line), ``best`` (the best frame as the
    corrected components' axes, e.g. ``'(-i, j, k)'``: flip the components
    along i), ``best_words``, ``ratio`` (its mean streamline over the one
    read), ``margin`` (the best's over the runner-up's), ``seeds`` and
    ``mean_length_mm`` (every frame and its mean, best first). A run whose
    verdict is 'mismatch' raises ValueError unless
    ``accept_misaligned_tensors=True``; an inconclusive check (few high-FA
    voxels, no clear winner) never stops one."""
    field = tensor_field(tensors, affine, mask, _tensor_options(tensor_order, tensor_frame, None, None, None, None,
                                                                accept_misaligned_tensors=True))
    return field.tensor_info["frame_check"]


def _distances(values, unreachable_value):
    distance = values["distance"]
    distance[~np.isfinite(distance)] = defaults.unreachable_value if unreachable_value is None else unreachable_value
    return distance


def tet_mesh_distance(points, tetrahedra, seeds, *, tensors=None, tensor_order=None, tensor_kind=None,
                      diffusion_metric=None, max_anisotropy=None, fa_threshold=None, method=None, k=None,
                      chain_measure=None, steiner=None, max_distance=None, unreachable_value=None, progress=None,
                      memory_check=True):
    """The geodesic distance over a tetrahedral mesh, as ``stvd distance
    MESH.node`` computes it: ``points`` (N, 3), ``tetrahedra`` (M, 4) vertex
    indices from 0, ``seeds`` vertex indices. ``tensors``: one per vertex in
    the frame of the points, (N, 6) in the order ``tensor_order`` states or
    (N, 3, 3); diffusion tensors unless ``tensor_kind='metric'``; none: the
    Euclidean metric. Tetrahedra with a vertex outside the domain are left
    out. ``memory_check`` as in ``stvd.distance``. Returns float64 distances
    per vertex (``unreachable_value`` where not reached)."""
    with progress_reporter(progress) as reporter:
        values = _core.tet_mesh_propagate(
            points, tetrahedra, index_list(seeds, "seeds"), tensors=tensors, tensor_order=tensor_order,
            tensor_kind=tensor_kind, diffusion_metric=diffusion_metric, max_anisotropy=max_anisotropy,
            fa_threshold=fa_threshold, method=method, k=k, chain_measure=chain_measure, steiner=steiner,
            max_distance=max_distance, progress=reporter.callback, memory_check=bool(memory_check))
        reporter.finish(values["finalized_vertices"])
    return _distances(values, unreachable_value)


def surface_distance(vertices, faces, seeds, *, metric="isotropic", metric_values=None, anisotropy=None,
                     tensor_order=None, method=None, k=None, chain_measure=None, steiner=None, max_distance=None,
                     unreachable_value=None, progress=None, memory_check=True):
    """The geodesic distance over a polygon surface, as ``stvd distance
    MESH.obj`` computes it: ``vertices`` (N, 3), ``faces`` (F, 3) or a list of
    polygons (vertex indices from 0), ``seeds`` vertex indices. ``metric``:
    ``'isotropic'``, ``'curvature'`` (with ``anisotropy``), ``'field'`` (a
    direction per vertex in ``metric_values``, with ``anisotropy``),
    ``'tensors'`` or ``'face-tensors'`` (world tensors per vertex or face in
    ``metric_values``: (N, 6) in ``tensor_order`` or (N, 3, 3)), ``'scale'``
    (a positive number per vertex in ``metric_values``: a step near the
    vertex costs that much times its length).
    ``memory_check`` as in ``stvd.distance``. Returns float64 distances per
    vertex (``unreachable_value`` where not reached)."""
    with progress_reporter(progress) as reporter:
        values = _core.surface_propagate(
            vertices, faces, index_list(seeds, "seeds"), metric=metric, metric_values=metric_values,
            anisotropy=anisotropy, tensor_order=tensor_order, method=method, k=k, chain_measure=chain_measure,
            steiner=steiner, max_distance=max_distance, progress=reporter.callback,
            memory_check=bool(memory_check))
        reporter.finish(values["finalized_vertices"])
    return _distances(values, unreachable_value)


def read_surface(path):
    """A surface file as ``stvd distance`` reads it: .obj, .off, .ply, .stl,
    a GIfTI surface (.surf.gii) or a FreeSurfer surface (lh.pial, ...).
    Returns a dict: ``vertices`` (N, 3) float64 as the file stores them,
    ``faces`` (F, 3) int64 (a list of polygons when not all are
    triangles), ``format``, ``coordinate_space`` ('tkr-RAS', 'scanner RAS'
    or GIfTI's DataSpace; '' when the file says nothing), ``transform``
    (4 x 4 to ``transformed_space``, e.g. FreeSurfer's tkr-RAS to scanner
    RAS from the volume geometry; None when the file gives none) and
    ``anatomical_structure`` (GIfTI's AnatomicalStructurePrimary,
    CortexLeft/CortexRight for lh.*/rh.*)."""
    return _core.read_surface(os.fspath(path))


def read_surface_values(path, vertex_count):
    """One number per vertex from a GIfTI func/shape file (its first data
    array), a FreeSurfer curv file or an .mgh/.mgz file: float64 (N,).
    ValueError when the file holds another count than ``vertex_count``."""
    return _core.read_surface_values(os.fspath(path), int(vertex_count))


def read_surface_regions(path, vertex_count):
    """Regions of the vertices from a FreeSurfer annotation (.annot), label
    (.label: its vertices are region 1) or GIfTI label file (.label.gii).
    Returns ``(keys, names)``: int32 (N,) keys (-1: in no region of an
    annotation or label) and a dict key -> name."""
    return _core.read_surface_regions(os.fspath(path), int(vertex_count))


def region_vertices(path, vertex_count, *names):
    """The vertices (sorted int64) of the regions ``names`` of a region file
    (read_surface_regions); ValueError naming the file's regions when one
    is not there."""
    keys, table = read_surface_regions(path, vertex_count)
    wanted = []
    for name in names:
        found = [k for k, n in table.items() if n == name]
        if not found:
            raise ValueError(f"{os.fspath(path)}: no region named {name!r} (the file names "
                             f"{', '.join(table.values()) or 'none'})")
        wanted.append(found[0])
    return np.flatnonzero(np.isin(keys, wanted)).astype(np.int64)


def write_surface_values(path, values, *, name="geodesic distance", anatomical_structure="", face_count=0):
    """Writes one value per vertex (float32) as a GIfTI shape/func file
    (.shape.gii: NIFTI_INTENT_SHAPE; .func.gii or .gii: NIFTI_INTENT_NONE) or
    a FreeSurfer curv file (.curv, lh.NAME, rh.NAME; ``face_count`` goes into
    its header), as ``stvd distance`` writes them. Non-finite values are
    written as NaN, which viewers leave uncoloured. Staged and renamed: a
    failed write leaves no file."""
    values = np.asarray(values, dtype=np.float64).ravel()
    values = np.where(np.isfinite(values), values, np.nan)
    path = os.fspath(path)
    with OutputFiles({"surface values": path}) as outputs:
        outputs.write(path, lambda staging: _core.write_surface_values(
            staging, values, str(name), str(anatomical_structure), int(face_count)))


def surface_region_distances(vertices, faces, regions, *, metric="isotropic", metric_values=None, anisotropy=None,
                             tensor_order=None, method=None, k=None, chain_measure=None, max_distance=None,
                             threads=None, keep_maps=False, unreachable_value=None, memory_check=True):
    """Geodesic distances between the regions of a surface and from every
    vertex to its nearest region, as ``stvd distance --region-matrix`` and
    ``--nearest-region`` compute them: one propagation per region (all the
    region's vertices are its sources), ``threads`` at once (None: one per
    core; the results do not depend on it). ``regions``: a list of vertex
    index arrays, one per region (``region_vertices`` reads them from an
    annotation or label file). The other keywords as in
    ``surface_distance``. Returns a dict: ``matrix`` (R, R), row a, column b
    the shortest distance from region a to a vertex of region b (0 on the
    diagonal); ``nearest_region`` (N,) int64, the index of each vertex's
    nearest region (-1: none reaches it; ties: the lower index);
    ``nearest_distance`` (N,); and with ``keep_maps`` ``maps`` (R, N), each
    region's distance map. Unreached distances are ``unreachable_value``
    (default inf)."""
    result = _core.surface_region_distances(
        vertices, faces, [index_list(r, "regions") for r in regions], metric=metric, metric_values=metric_values,
        anisotropy=anisotropy, tensor_order=tensor_order, method=method, k=k, chain_measure=chain_measure,
        max_distance=max_distance, threads=0 if threads is None else int(threads), keep_maps=bool(keep_maps),
        memory_check=bool(memory_check))
    if unreachable_value is not None:
        for key in ("matrix", "nearest_distance", "maps"):
            if key in result:
                result[key] = np.where(np.isfinite(result[key]), result[key], unreachable_value)
    return result


class SurfaceSolver:
    """A surface and its metric built once, then queried with many seed sets,
    as potpourri3d's ``MeshHeatMethodDistanceSolver`` keeps its
    precomputation (the surface's rings and frames, the metric, the split of
    a non-manifold mesh)::

        solver = stvd.SurfaceSolver(vertices, faces)
        d = solver.distance([12])                      # as stvd.surface_distance(vertices, faces, [12])
        maps = solver.distances([[12], [40, 41], [99]], threads=None)   # (3, N), on all cores
        path = solver.paths([12], [500])[0]            # (M, 3) points from vertex 500 back to 12
        regions = solver.region_distances([a, b, c])   # as stvd.surface_region_distances

    The keywords of the constructor are those of ``surface_distance``
    (``metric``, ``metric_values``, ``anisotropy``, ``tensor_order``,
    ``method`` 'stvd' or 'dijkstra', ``k``, ``chain_measure``,
    ``max_distance``, ``memory_check``). Every query gives exactly what
    ``surface_distance`` gives for the same seeds, whatever ``threads`` is
    (None: one per core). ``paths`` follows the propagation's predecessors
    from each target to a seed: a path along the surface's edges whose
    length is at least the distance (the distance itself is measured along
    straighter lines across the faces); an unreached target gives an empty
    path. Unreached distances are ``unreachable_value`` (default inf)."""

    def __init__(self, vertices, faces, *, metric="isotropic", metric_values=None, anisotropy=None,
                 tensor_order=None, method=None, k=None, chain_measure=None, max_distance=None,
                 unreachable_value=None, memory_check=True):
        self._solver = _core.SurfaceSolver(
            vertices, faces, metric=metric, metric_values=metric_values, anisotropy=anisotropy,
            tensor_order=tensor_order, method=method, k=k, chain_measure=chain_measure, max_distance=max_distance,
            memory_check=bool(memory_check))
        self._unreachable = unreachable_value

    @property
    def vertex_count(self):
        return self._solver.vertex_count

    def _out(self, values):
        if self._unreachable is None:
            return values
        return np.where(np.isfinite(values), values, self._unreachable)

    def distance(self, seeds):
        """Float64 distances per vertex from the seed vertices."""
        return self._out(self._solver.distance(index_list(seeds, "seeds")))

    def distances(self, seed_sets, threads=None):
        """One map per seed set, (S, N), ``threads`` propagations at once."""
        sets = [index_list(s, "seed_sets") for s in seed_sets]
        return self._out(self._solver.distances(sets, 0 if threads is None else int(threads)))

    def paths(self, seeds, targets):
        """For each target vertex, the (M, 3) points of its path back to the
        seeds along the propagation's predecessors, target first."""
        return self._solver.paths(index_list(seeds, "seeds"), index_list(targets, "targets"))

    def region_distances(self, regions, threads=None, keep_maps=False):
        """Distances between regions and to the nearest region, as
        ``surface_region_distances``."""
        result = self._solver.region_distances([index_list(r, "regions") for r in regions],
                                               0 if threads is None else int(threads), bool(keep_maps))
        for key in ("matrix", "nearest_distance", "maps"):
            if key in result:
                result[key] = self._out(result[key])
        return result
