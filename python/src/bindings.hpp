// The parts of the extension module stvd._core, each registered by its own
// translation unit.
#pragma once

#include <pybind11/pybind11.h>

#include <stdexcept>

namespace stvd::python {

/// A run that would not fit into the memory available, refused before it
/// starts (the tool's exit code 6): MemoryError in Python.
class MemoryShortfallError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// TensorField and VolumePropagation: tensor volumes, paths, connectivity.
void bindVolumes(pybind11::module_& m);
/// tet_mesh_propagate and surface_propagate.
void bindMeshes(pybind11::module_& m);
/// RunFiles and OutputTransaction: what a call writes, checked and atomic.
void bindFiles(pybind11::module_& m);
/// GIfTI and FreeSurfer surfaces, per-vertex values and regions
/// (surface_file_bindings.cpp).
void bindSurfaceFiles(pybind11::module_& m);
/// stvd.fod_distance, fod_paths and fod_connectivity (fod_bindings.cpp).
void bindFod(pybind11::module_& m);

}  // namespace stvd::python
