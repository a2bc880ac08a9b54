// Cortical surface files from Python (stvd.read_surface,
// stvd.read_surface_values, stvd.read_surface_regions,
// stvd.write_surface_values): the library's own readers and writers of
// GIfTI and FreeSurfer files (stvd/surface_io/cortical_surface_files.hpp),
// so that the package reads what the tool reads, the same way.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "bindings.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

namespace py = pybind11;

namespace stvd::python {
namespace {

py::dict readSurface(const std::string& path) {
  surface_io::SurfaceMesh mesh;
  {
    py::gil_scoped_release release;
    mesh = surface_io::readSurfaceMesh(path);
  }
  py::array_t<double> vertices({static_cast<py::ssize_t>(mesh.points.size()), py::ssize_t{3}});
  auto v = vertices.mutable_unchecked<2>();
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    v(i, 0) = mesh.points[i].x;
    v(i, 1) = mesh.points[i].y;
    v(i, 2) = mesh.points[i].z;
  }
  py::dict d;
  d["vertices"] = vertices;
  bool triangles = true;
  for (std::size_t f = 0; f < mesh.faces.faceCount(); ++f)
    triangles = triangles && mesh.faces.faceStart[f + 1] - mesh.faces.faceStart[f] == 3;
  if (triangles) {
    py::array_t<std::int64_t> faces({static_cast<py::ssize_t>(mesh.faces.faceCount()), py::ssize_t{3}});
    auto f = faces.mutable_unchecked<2>();
    for (std::size_t i = 0; i < mesh.faces.faceCount(); ++i)
      for (int c = 0; c < 3; ++c) f(i, c) = mesh.faces.faceVertex[3 * i + c];
    d["faces"] = faces;
  } else {
    py::list faces;
    for (std::size_t i = 0; i < mesh.faces.faceCount(); ++i) {
      py::list polygon;
      for (std::uint32_t c = mesh.faces.faceStart[i]; c < mesh.faces.faceStart[i + 1]; ++c)
        polygon.append(mesh.faces.faceVertex[c]);
      faces.append(polygon);
    }
    d["faces"] = faces;
  }
  d["format"] = mesh.format;
  d["coordinate_space"] = mesh.coordinates.space;
  if (mesh.coordinates.hasTransform) {
    py::array_t<double> t({py::ssize_t{4}, py::ssize_t{4}});
    auto a = t.mutable_unchecked<2>();
    for (int i = 0; i < 16; ++i) a(i / 4, i % 4) = mesh.coordinates.transform[i];
    d["transform"] = t;
    d["transformed_space"] = mesh.coordinates.transformedSpace;
  } else {
    d["transform"] = py::none();
    d["transformed_space"] = py::none();
  }
  d["anatomical_structure"] = mesh.anatomicalStructure;
  return d;
}

py::array_t<double> readValues(const std::string& path, std::size_t vertexCount) {
  std::vector<double> values;
  {
    py::gil_scoped_release release;
    values = surface_io::readVertexValues(path, vertexCount);
  }
  return py::array_t<double>(values.size(), values.data());
}

py::tuple readRegions(const std::string& path, std::size_t vertexCount) {
  surface_io::VertexRegions regions;
  {
    py::gil_scoped_release release;
    regions = surface_io::readVertexRegions(path, vertexCount);
  }
  py::dict names;
  for (const auto& [key, name] : regions.name) names[py::int_(key)] = name;
  return py::make_tuple(py::array_t<std::int32_t>(regions.key.size(), regions.key.data()), names);
}

void writeValues(const std::string& path, const std::vector<double>& values, const std::string& name,
                 const std::string& anatomicalStructure, std::size_t faceCount) {
  if (surface_io::vertexValuesFormatOf(path) == surface_io::VertexValuesFormat::None)
    throw py::value_error(path + ": write_surface_values writes .shape.gii, .func.gii, .gii, .curv or lh.* / rh.* "
                                 "(FreeSurfer curv)");
  surface_io::SurfaceMesh mesh;
  mesh.points.resize(values.size());
  for (std::size_t f = 0; f < faceCount; ++f) mesh.faces.faceStart.push_back(0);
  mesh.anatomicalStructure = anatomicalStructure;
  py::gil_scoped_release release;
  surface_io::writeVertexValues(path, path, mesh, values, name);
}

}  // namespace

void bindSurfaceFiles(py::module_& m) {
  m.def("read_surface", &readSurface, py::arg("path"));
  m.def("read_surface_values", &readValues, py::arg("path"), py::arg("vertex_count"));
  m.def("read_surface_regions", &readRegions, py::arg("path"), py::arg("vertex_count"));
  m.def("write_surface_values", &writeValues, py::arg("path"), py::arg("values"), py::arg("name"),
        py::arg("anatomical_structure"), py::arg("face_count"));
}

}  // namespace stvd::python
