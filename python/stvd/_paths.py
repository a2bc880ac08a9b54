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
