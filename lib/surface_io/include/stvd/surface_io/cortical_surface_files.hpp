// The files of cortical surface analysis: GIfTI (surfaces, per-vertex
// values, label tables) and FreeSurfer (binary triangle surfaces, curv
// files, .mgh/.mgz per-vertex volumes, .annot annotations, .label files).
// Our own parsers (zlib for the compressed encodings, nothing else), regular
// files only; every error is a MeshFileError naming the file. See
// docs/surfaces.md, "Cortical surfaces".
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "stvd/surface_io/surface_mesh_io.hpp"

namespace stvd::surface_io {

/// True when the path ends in .gii (any letter case).
bool isGiftiPath(const std::string& path);
/// True when the file's first three bytes are FreeSurfer's triangle-surface
/// magic number (0xFF 0xFF 0xFE). False for anything that is not a
/// readable regular file; never blocks.
bool isFreeSurferSurfaceFile(const std::string& path);
/// True for FreeSurfer's file naming of per-hemisphere files: a name that
/// starts with "lh." or "rh." (lh.pial, rh.white, lh.thickness).
bool hasFreeSurferHemisphereName(const std::string& path);

/// GIfTI surface (*.surf.gii): the NIFTI_INTENT_POINTSET array (N x 3) and
/// the NIFTI_INTENT_TRIANGLE array (F x 3, vertices from 0), encoded as
/// ASCII, Base64Binary or GZipBase64Binary, either byte order, row- or
/// column-major. The coordinates are kept as the file stores them (its
/// DataSpace); the pointset's CoordinateSystemTransformMatrix is kept in
/// `coordinates`. External data files are refused.
SurfaceMesh readGiftiSurface(const std::string& path);
/// FreeSurfer binary triangle surface (lh.pial, lh.white, ...): magic
/// 0xFFFFFE, a "created by" line, counts, big-endian float32 coordinates
/// and int32 triangles, then the optional tags: useRealRAS (coordinates in
/// scanner RAS instead of tkr-RAS) and the volume geometry, whose c_ras and
/// axes give the transform from tkr-RAS to scanner RAS.
SurfaceMesh readFreeSurferSurface(const std::string& path);

/// One number per vertex: a GIfTI functional/shape file (*.func.gii,
/// *.shape.gii: its first data array, N or N x 1 values), a FreeSurfer curv
/// file (new format 0xFFFFFF, or the old 3-byte-count format, by the magic
/// number) or an .mgh/.mgz file with N voxels in one frame. Throws
/// MeshFileError when the file holds another count than `vertexCount`.
std::vector<double> readVertexValues(const std::string& path, std::size_t vertexCount);
/// True when readVertexValues reads the path by its name: .gii, .mgh, .mgz,
/// .curv, or a FreeSurfer hemisphere name.
bool isVertexValuesPath(const std::string& path);

/// A parcellation of the vertices: a key per vertex and the keys' names.
struct VertexRegions {
  std::vector<std::int32_t> key;           ///< one per vertex
  std::map<std::int32_t, std::string> name;  ///< the names of the keys the file defines
  /// The key of vertices in no region (the annotation's unassigned
  /// vertices: -1; GIfTI label 0 is a region like any other when named).
  static constexpr std::int32_t kNoRegion = -1;
};
/// Regions of the vertices: a FreeSurfer annotation (.annot: the colour
/// table's names; vertices whose colour is in no entry have kNoRegion), a
/// FreeSurfer label file (.label: its vertices form region 1, named by the
/// file name without ".label"; the others have kNoRegion) or a GIfTI label
/// file (*.label.gii: NIFTI_INTENT_LABEL keys and the LabelTable's names).
VertexRegions readVertexRegions(const std::string& path, std::size_t vertexCount);
/// True when the path ends in .annot, .label or .label.gii.
bool isVertexRegionsPath(const std::string& path);
/// The vertices of the region named `name` (exact match); MeshFileError
/// naming `path` and listing the names when there is none, or when the
/// region has no vertex.
std::vector<VertexId> regionVertices(const VertexRegions& regions, const std::string& name,
                                     const std::string& path);

/// How a per-vertex output file is written: GIfTI (*.shape.gii: intent
/// NIFTI_INTENT_SHAPE; *.func.gii or another .gii: NIFTI_INTENT_NONE) or a
/// FreeSurfer curv file (*.curv, or a name starting with lh. or rh.).
enum class VertexValuesFormat { None, Gifti, FreeSurferCurv };
VertexValuesFormat vertexValuesFormatOf(const std::string& path);

/// Writes one value per vertex as `formatPath` names the format (the two
/// paths differ when the caller stages the file). GIfTI: one FLOAT32 data
/// array, GZipBase64Binary (zlib, then base64) little-endian, MetaData Name=`name` and, when
/// `mesh` has one, the AnatomicalStructurePrimary Connectome Workbench uses;
/// curv: the new format, float32 big-endian, with the mesh's face count.
/// Values are written as float32 (NaN and infinities too).
void writeVertexValues(const std::string& path, const std::string& formatPath, const SurfaceMesh& mesh,
                       const std::vector<double>& values, const std::string& name);

}  // namespace stvd::surface_io
