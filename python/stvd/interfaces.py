"""Nipype interfaces of stvd: ``Distance``, ``Path`` and ``Connectivity``.

Nodes of an existing Nipype workflow, run by any of its plugins (MultiProc,
SLURM, SGE, ...). Each runs the package's calls in the node's process and
writes its output atomically into the node's folder (``out_file``, named
by the input of that name) through ``stvd.OutputFiles``: never over one of
its inputs, whole or not at all, the bytes the tool writes. Inputs follow Nipype's names (``in_file`` for
the tensors, ``mask_file``, ``out_file``) and the tool's options; options
left undefined take ``stvd.defaults``::

    from nipype import Node
    from stvd.interfaces import Distance
    node = Node(Distance(seed_voxels=[(55, 54, 15)]), name="distance")
    node.inputs.in_file = "dti_tensor_dipy5d.nii.gz"

Needs Nipype (Debian: python3-nipype).
"""

import os

from nipype.interfaces.base import BaseInterface, BaseInterfaceInputSpec, File, TraitedSpec, isdefined, traits

from ._outputs import OutputFiles

__all__ = ["Distance", "Path", "Connectivity"]

_VOXEL = traits.Tuple(traits.Int, traits.Int, traits.Int)
_POINT = traits.Tuple(traits.Float, traits.Float, traits.Float)


class _TensorInputSpec(BaseInterfaceInputSpec):
    """What every stvd node takes: the tensors, the domain and the method."""

    in_file = File(exists=True, mandatory=True, desc="tensor volume (NIfTI or NRRD), read as stvd distance reads it")
    mask_file = File(exists=True, desc="mask on the tensors' grid: voxels where it is 0 are outside the domain")
    tensor_order = traits.Enum("lower", "fsl", "mrtrix", desc="component order of six-volume files (--tensor-order)")
    tensor_frame = traits.Enum("voxel", "world", desc="frame of the tensor components (--tensor-frame)")
    tensor_kind = traits.Enum("diffusion", "metric", desc="--tensor-kind")
    diffusion_metric = traits.Str(desc="--diffusion-metric")
    max_anisotropy = traits.Float(desc="--max-anisotropy")
    fa_threshold = traits.Float(desc="--fa-threshold")
    method = traits.Str(desc="stvd, dijkstra or lanthier (--method)")
    k = traits.Int(desc="STVD memory depth (--k)")
    chain_measure = traits.Str(desc="how STVD measures a chain of edges (--chain-measure)")
    stencil = traits.Str(desc="neighbourhood stencil: 6, 18, 26, 98 or 290 (--stencil)")


class _SeedInputSpec(_TensorInputSpec):
    seed_voxels = traits.List(_VOXEL, desc="seed voxels (i, j, k), 0-based (--seed-voxel)")
    seed_points = traits.List(_POINT, desc="seed points in RAS millimetres (--seed-point)")
    seed_file = File(exists=True, desc="label image: every non-zero voxel in the domain is a seed (--seeds)")
    max_distance = traits.Float(desc="stop at this distance in mm (--max-distance)")


class _OutputSpec(TraitedSpec):
    out_file = File(exists=True, desc="the output file")


def _defined(inputs, names):
    """The inputs among ``names`` that are set, as keywords."""
    values = {}
    for name in names:
        value = getattr(inputs, name)
        if isdefined(value):
            values[name] = value
    return values


_TENSOR_NAMES = ("tensor_order", "tensor_frame", "tensor_kind", "diffusion_metric", "max_anisotropy", "fa_threshold",
                 "method", "k", "chain_measure", "stencil")


class _StvdInterface(BaseInterface):
    output_spec = _OutputSpec

    def _out_path(self):
        return os.path.abspath(self.inputs.out_file)

    def _output_files(self):
        """The node's output, checked against its inputs however spelled
        (``stvd.FileConflictError`` before anything is computed), to be
        written within a ``with`` block."""
        inputs = [(f"{name} input", getattr(self.inputs, name))
                  for name in ("in_file", "mask_file", "seed_file", "target_file", "labels_file")
                  if self.inputs.trait(name) is not None and isdefined(getattr(self.inputs, name))]
        return OutputFiles({"output out_file": self._out_path()}, inputs=inputs)

    def _propagation(self):
        import stvd

        seeds = _defined(self.inputs, ("seed_voxels", "seed_points", "seed_file", "max_distance"))
        return stvd.propagate(self.inputs.in_file, seeds.get("seed_voxels"), seed_points=seeds.get("seed_points"),
                              seed_labels=seeds.get("seed_file"), max_distance=seeds.get("max_distance"),
                              mask=self.inputs.mask_file if isdefined(self.inputs.mask_file) else None,
                              **_defined(self.inputs, _TENSOR_NAMES))

    def _list_outputs(self):
        return {"out_file": self._out_path()}


class _DistanceInputSpec(_SeedInputSpec):
    unreachable_value = traits.Float(desc="value of voxels not reached (--unreachable-value)")
    out_file = File("distance.nii.gz", usedefault=True,
                    desc="the distance map (float32 mm; NIfTI, NRRD or MRtrix by the extension)")


class Distance(_StvdInterface):
    """The geodesic distance map from seeds, as ``stvd distance`` computes it."""

    input_spec = _DistanceInputSpec

    def _run_interface(self, runtime):
        unreachable = self.inputs.unreachable_value if isdefined(self.inputs.unreachable_value) else None
        with self._output_files() as out:
            self._propagation().save(self._out_path(), unreachable, outputs=out)
        return runtime


class _PathInputSpec(_SeedInputSpec):
    target_voxels = traits.List(_VOXEL, desc="target voxels (i, j, k) (--target-voxel)")
    target_points = traits.List(_POINT, desc="target points in RAS millimetres (--target-point)")
    target_file = File(exists=True, desc="label image: one path to each region (--targets)")
    out_file = File("paths.trk", usedefault=True,
                    desc="the paths as stvd path writes them: .trk, .tck or .vtk in RAS millimetres")


class Path(_StvdInterface):
    """Geodesic paths from targets back to the seeds, as ``stvd path``
    traces and writes them."""

    input_spec = _PathInputSpec

    def _run_interface(self, runtime):
        import stvd

        out = self._output_files()
        targets = _defined(self.inputs, ("target_voxels", "target_points", "target_file"))
        paths = stvd.trace_paths(self._propagation(), targets.get("target_voxels"),
                                 target_points=targets.get("target_points"),
                                 target_labels=targets.get("target_file"))
        with out:
            paths.save(self._out_path(), outputs=out)
        return runtime


class _ConnectivityInputSpec(_TensorInputSpec):
    labels_file = File(exists=True, mandatory=True, desc="region image on the tensors' grid (--labels)")
    threads = traits.Int(1, usedefault=True, desc="regions propagated at once (--threads); 1 under a plugin "
                                                   "that runs a node per core")
    out_file = File("connectivity.tsv", usedefault=True, desc="the table of stvd connectivity")


class Connectivity(_StvdInterface):
    """Geodesic distance and connectivity between every pair of regions, as
    ``stvd connectivity`` computes it, written as its table."""

    input_spec = _ConnectivityInputSpec

    def _run_interface(self, runtime):
        import stvd

        from ._subject import connectivity_table

        out = self._output_files()
        result = stvd.connectivity(self.inputs.in_file, self.inputs.labels_file, threads=self.inputs.threads,
                                   mask=self.inputs.mask_file if isdefined(self.inputs.mask_file) else None,
                                   **_defined(self.inputs, _TENSOR_NAMES))
        with out:
            out.write_text(self._out_path(), connectivity_table(result))
        return runtime
