// FreeSurfer's file formats, read from their bytes. Private to surface_io;
// the public entry points are in cortical_surface_files.hpp.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "stvd/surface_io/cortical_surface_files.hpp"

namespace stvd::surface_io::detail {

/// The whole regular file, or MeshFileError naming it.
std::string readFileBytes(const std::string& path);
SurfaceMesh readFreeSurferSurfaceBytes(const std::string& path, const std::string& bytes);
std::vector<double> readCurv(const std::string& path, const std::string& bytes, std::size_t vertexCount);
std::vector<double> readMgh(const std::string& path, std::size_t vertexCount);
VertexRegions readAnnot(const std::string& path, std::size_t vertexCount);
VertexRegions readLabelFile(const std::string& path, std::size_t vertexCount);

}  // namespace stvd::surface_io::detail
