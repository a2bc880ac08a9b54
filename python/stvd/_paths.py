"""Geodesic paths as Python objects, and as a NiBabel tractogram."""

import numpy as np


class Paths(list):
    """Geodesic paths: a list of ``(N, 3)`` float64 arrays of RAS millimetres,
    each from its seed end (first point) to its target (last point), with the
    per-path figures of ``stvd path`` as arrays in the same order:

    - ``geodesic_mm``: the distance value at the target (the path's geodesic
      length, what ``stvd distance`` writes there);
    - ``euclidean_mm``: the length of the polyline;
    - ``straight_mm``: the distance between the target and the seed voxel;
    - ``metric_length_mm``: the polyline measured with the metric (NaN for
      discrete paths);
    - ``mean_fa``: the FA of the diffusion tensors along the path, weighted by
      length (NaN with ``tensor_kind='metric'``); ``fa`` holds it per point;
    - ``targets`` (how each target was given), ``target_voxels``,
      ``seed_voxels``, ``gradient_steps``, ``discrete_points``,
      ``fallbacks`` (dicts of fallback kind to count) and
      ``refine_iterations``.

    ``affine``, ``shape``, ``zooms`` and ``axis_codes`` describe the grid of
    the tensors, for a ``.trk`` header (see ``trk_header``). ``save`` writes
    them as ``stvd path`` does; ``input_files`` are the files they come from.
    """

    _PER_PATH_ARRAYS = ("target_voxels", "seed_voxels", "geodesic_mm", "euclidean_mm", "straight_mm",
                        "metric_length_mm", "mean_fa", "gradient_steps", "discrete_points", "refine_iterations")
    _PER_PATH_LISTS = ("targets", "fa", "fallbacks")

    def __init__(self, records, affine, shape, zooms, axis_codes, propagation=None, input_files=()):
        super().__init__(r["points"] for r in records)
        self.targets = [r["target"] for r in records]
        self.target_voxels = np.array([r["target_voxel"] for r in records], dtype=np.int64).reshape(-1, 3)
        self.seed_voxels = np.array([r["seed_voxel"] for r in records], dtype=np.int64).reshape(-1, 3)
        for key in ("geodesic_mm", "euclidean_mm", "straight_mm", "metric_length_mm", "mean_fa"):
            setattr(self, key, np.array([r[key] for r in records], dtype=np.float64))
        self.fa = [r["fa"] for r in records]
        self.gradient_steps = np.array([r["gradient_steps"] for r in records], dtype=np.int64)
        self.discrete_points = np.array([r["discrete_points"] for r in records], dtype=np.int64)
        self.fallbacks = [r["fallbacks"] for r in records]
        self.refine_iterations = np.array([r["refine_iterations"] for r in records], dtype=np.int64)
        self.affine = affine
        self.shape = shape
        self.zooms = zooms
        self.axis_codes = axis_codes
        self._propagation = propagation
        self.input_files = [(role, path) for role, path in input_files if path]
        self.fod_run = None  # stvd.fod_paths: the run's record, for its QC page (stvd.report)

    def _with(self, lines, per_path):
        """Paths on this grid holding `lines` and the per-path values given."""
        out = Paths([], self.affine, self.shape, self.zooms, self.axis_codes, self._propagation, self.input_files)
        out.fod_run = self.fod_run
        out.extend(lines)
        for name, value in per_path.items():
            setattr(out, name, value)
        return out

    @staticmethod
    def merge(*paths):
        """One ``stvd.Paths`` of several, in order, with their per-path figures:
        paths of several runs (other seeds, other options) on the same grid,
        which ``stvd.tractogram`` and ``save`` take as one. Paths on another
        grid (another affine or shape: another image or subject) are refused
        with a ValueError, as a ``.trk`` file has one grid; ``paths + paths``
        is the same for two."""
        if len(paths) == 1 and not isinstance(paths[0], Paths):
            paths = tuple(paths[0])  # an iterable of Paths
        if not paths:
            raise ValueError("Paths.merge: no paths given")
        for n, p in enumerate(paths):
            if not isinstance(p, Paths):
                raise TypeError(f"Paths.merge: argument {n} is a {type(p).__name__}, not stvd.Paths (the figures "
                                "of each path and its grid come with stvd.Paths)")
        first = paths[0]
        for p in paths[1:]:
            if tuple(p.shape) != tuple(first.shape) or not np.array_equal(p.affine, first.affine):
                raise ValueError(
                    f"Paths.merge: paths on another grid (shape {tuple(p.shape)}, affine {np.round(p.affine, 4).tolist()}) "
                    f"than the first (shape {tuple(first.shape)}, affine {np.round(first.affine, 4).tolist()}); paths "
                    "merge only on the grid of one image")
        lines = [line for p in paths for line in p]
        per_path = {}
        for name in Paths._PER_PATH_ARRAYS:
            per_path[name] = np.concatenate([getattr(p, name) for p in paths])
        for name in Paths._PER_PATH_LISTS:
            per_path[name] = [value for p in paths for value in getattr(p, name)]
        merged = first._with(lines, per_path)
        merged.input_files = list(dict.fromkeys(f for p in paths for f in p.input_files))
        return merged

    def __add__(self, other):
        if not isinstance(other, Paths):
            return NotImplemented
        return Paths.merge(self, other)

    def __iadd__(self, other):
        # list's += would add the lines without their figures.
        if not isinstance(other, Paths):
            return NotImplemented
        return Paths.merge(self, other)

    def __getitem__(self, index):
        """One path's points for an integer, ``stvd.Paths`` for a slice."""
        if isinstance(index, slice):
            per_path = {name: getattr(self, name)[index] for name in Paths._PER_PATH_ARRAYS + Paths._PER_PATH_LISTS}
            return self._with(list.__getitem__(self, index), per_path)
        return list.__getitem__(self, index)

    def save(self, path, *, outputs=None):
        """Writes the paths to ``path`` (``.tck``, ``.trk`` or ``.vtk``) as
        ``stvd path -o path`` writes them, byte for byte: RAS millimetres,
        ``geodesic_mm``, ``euclidean_mm`` and ``mean_fa`` per path, ``fa``
        per point, a ``.trk`` header on the tensors' grid. Never over one of
        ``input_files``, atomically; within ``outputs`` (a
        ``stvd.OutputFiles``) it appears at the commit."""
        from ._outputs import OutputFiles

        if outputs is None:
            with OutputFiles({"paths file": path}, inputs=self.input_files) as files:
                self.save(path, outputs=files)
            return
        outputs._require_inputs(self.input_files, "the paths")
        with_fa = len(self) > 0 and all(fa is not None for fa in self.fa)
        self._propagation._result.write_paths(
            outputs._transaction, outputs._declared_output(path), list(self), self.geodesic_mm.tolist(),
            self.euclidean_mm.tolist(), mean_fa=self.mean_fa.tolist() if with_fa else None,
            fa=self.fa if with_fa else None)

    def trk_header(self):
        """The header that places a ``.trk`` file on the tensors' grid, as
        ``stvd path`` writes it: pass it to ``nibabel.streamlines.save``."""
        from nibabel.streamlines import Field

        return {
            Field.VOXEL_TO_RASMM: self.affine,
            Field.DIMENSIONS: np.array(self.shape, dtype=np.int16),
            Field.VOXEL_SIZES: np.array(self.zooms, dtype=np.float32),
            Field.VOXEL_ORDER: self.axis_codes,
        }


def tractogram(paths):
    """The paths as a ``nibabel.streamlines.Tractogram`` in RAS millimetres,
    with ``geodesic_mm``, ``euclidean_mm`` and (for diffusion tensors)
    ``mean_fa`` per streamline and ``fa`` per point, as ``stvd path`` writes
    them. Save it with ``nibabel.streamlines.save(t, 'paths.tck')``, or as
    ``.trk`` on the tensors' grid with ``header=paths.trk_header()``."""
    from nibabel.streamlines import Tractogram

    if not isinstance(paths, Paths):
        raise TypeError(f"paths: expected the stvd.Paths of stvd.trace_paths, got a {type(paths).__name__} (merge "
                        "the paths of several runs with paths_a + paths_b or stvd.Paths.merge)")
    per_streamline = {
        "geodesic_mm": paths.geodesic_mm.astype(np.float32).reshape(-1, 1),
        "euclidean_mm": paths.euclidean_mm.astype(np.float32).reshape(-1, 1),
    }
    per_point = {}
    if all(fa is not None for fa in paths.fa) and len(paths):
        per_streamline["mean_fa"] = paths.mean_fa.astype(np.float32).reshape(-1, 1)
        per_point["fa"] = [fa.reshape(-1, 1) for fa in paths.fa]
    return Tractogram(list(paths), data_per_streamline=per_streamline, data_per_point=per_point,
                      affine_to_rasmm=np.eye(4))
