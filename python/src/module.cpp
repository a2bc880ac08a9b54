// The extension module stvd._core: the library's defaults, its errors as
// Python exceptions, and the bindings of volumes and meshes. The public API
// is the pure-Python package around it (python/stvd/).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "stvd/cell_mesh/cell_mesh_domain.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/surface/surface_lanthier.hpp"

namespace py = pybind11;

namespace {

/// Every default the Python API has, from the library's own constants and
/// default-constructed options, so that the package follows the library:
/// the k a propagation runs with when none is given is its kind of
/// domain's (defaultMemoryDepth), as in the tool.
py::dict defaults() {
  using namespace stvd;
  const PropagationChoice choice;
  const imaging::TensorInputOptions tensor;
  const PathTracingOptions tracing;
  py::dict d;
  d["method"] = methodName(choice);
  d["k"] = memoryDepthOf<VoxelGridDomain>(choice);
  d["surface_k"] = memoryDepthOf<SurfaceDomain>(choice);
  d["tet_mesh_k"] = memoryDepthOf<CellMeshDomain>(choice);
  d["chain_measure"] = chainMeasureName(choice.chainMeasure);
  // One chain measure for every kind of domain; the key stays for scripts
  // written when surfaces had their own.
  d["surface_chain_measure"] = chainMeasureName(choice.chainMeasure);
  d["stencil"] = choice.stencil;
  d["domain_connectivity"] = static_cast<int>(choice.connectivity);
  d["tensor_kind"] = imaging::tensorKindName(tensor.metric.kind);
  d["diffusion_metric"] = imaging::diffusionMetricName(tensor.metric.diffusionMetric);
  // Unset: the cap depends on the tensor kind (diffusion tensors:
  // kDefaultMaxAnisotropy; a metric as given).
  d["max_anisotropy"] = tensor.metric.maxAnisotropy;
  d["diffusion_max_anisotropy"] = imaging::kDefaultMaxAnisotropy;
  d["accept_implausible_tensors"] = tensor.acceptImplausible;
  d["unreachable_value"] = kDefaultUnreachableValue;
  d["step"] = tracing.stepFraction;
  d["smooth"] = tracing.smoothingPasses;
  d["refine"] = tracing.refine;
  d["max_k"] = kMaxMemoryDepth;
  d["max_steiner"] = kMaxSteinerPoints;
  return d;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "stvd's C++ library: the extension module under the stvd package.";
  m.attr("__version__") = STVD_VERSION_TEXT;
  m.attr("NO_VERTEX") = stvd::kNoVertex;
  m.def("defaults", &defaults, "The library's defaults for every option of the Python API.");

  // The library's one-line messages become ValueError (its option, input and
  // domain errors derive from std::invalid_argument, which pybind11 already
  // turns into ValueError); file errors, which are runtime errors in C++,
  // are bad input here too. A run refused for lack of memory is MemoryError.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const stvd::imaging::ImageIoError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const stvd::python::MemoryShortfallError& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    }
  });

  stvd::python::bindFiles(m);
  stvd::python::bindVolumes(m);
  stvd::python::bindMeshes(m);
}
