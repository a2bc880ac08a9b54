#include "nrrd_header.hpp"

#include <NrrdIO.h>

#include <cstdlib>
#include <memory>

#include "library_messages.hpp"
#include "stvd/errors.hpp"

namespace stvd::imaging::detail {
namespace {

struct NrrdDeleter {
  void operator()(Nrrd* n) const { nrrdNuke(n); }
};
struct NrrdIoStateDeleter {
  void operator()(NrrdIoState* s) const { nrrdIoStateNix(s); }
};
using NrrdPtr = std::unique_ptr<Nrrd, NrrdDeleter>;

std::string takeBiffMessage() {
  char* err = biffGetDone(NRRD);
  std::string message = err ? err : "unknown NRRD error";
  std::free(err);
  for (char& c : message)
    if (c == '\n' || c == '\r') c = ' ';
  while (!message.empty() && message.back() == ' ') message.pop_back();
  return message;
}

NrrdPtr loadNrrd(const std::string& path, bool headerOnly) {
  NrrdPtr nrrd(nrrdNew());
  std::unique_ptr<NrrdIoState, NrrdIoStateDeleter> io(nrrdIoStateNew());
  io->skipData = headerOnly ? 1 : 0;
  LibraryMessageCapture quiet;
  if (nrrdLoad(nrrd.get(), path.c_str(), io.get()) != 0)
    throw ImageIoError(path, "cannot read the NRRD file: " + takeBiffMessage());
  return nrrd;
}

int rangeAxis(const Nrrd& nrrd) {
  for (unsigned a = 0; a < nrrd.dim; ++a)
    if (nrrd.axis[a].kind == nrrdKind3DMaskedSymMatrix || nrrd.axis[a].kind == nrrdKind3DSymMatrix)
      return static_cast<int>(a);
  return -1;
}

}  // namespace

bool nrrdSpaceIsLeftAnteriorSuperior(const std::string& path) {
  return loadNrrd(path, true)->space == nrrdSpaceLeftAnteriorSuperior;
}

NrrdTensorHeader readNrrdTensorHeader(const std::string& path) {
  const NrrdPtr nrrd = loadNrrd(path, true);
  NrrdTensorHeader header;
  if (nrrd->space != nrrdSpaceUnknown) header.space = airEnumStr(nrrdSpace, nrrd->space);
  // The conversions of the geometry on reading: ITK's for RAS; for LAS the
  // y flip, which geometryOfAxes (itk_io_support.cpp) applies to the grid in
  // place of ITK 5.2's x flip.
  switch (nrrd->space) {
    case nrrdSpaceRightAnteriorSuperior: header.spaceToLps = {-1, 0, 0, 0, -1, 0, 0, 0, 1}; break;
    case nrrdSpaceLeftAnteriorSuperior: header.spaceToLps = {1, 0, 0, 0, -1, 0, 0, 0, 1}; break;
    default: break;
  }
  if (nrrd->spaceDim == 3 && AIR_EXISTS(nrrd->measurementFrame[0][0])) {
    header.hasMeasurementFrame = true;
    // NrrdIO stores one frame vector per first index: measurementFrame[c]
    // is column c of the frame matrix.
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) header.measurementFrame[3 * r + c] = nrrd->measurementFrame[c][r];
  }
  const int range = rangeAxis(*nrrd);
  header.masked = range >= 0 && nrrd->axis[range].kind == nrrdKind3DMaskedSymMatrix;
  return header;
}

std::vector<float> readNrrdConfidence(const std::string& path) {
  const NrrdPtr nrrd = loadNrrd(path, false);
  const int range = rangeAxis(*nrrd);
  if (range < 0 || nrrd->axis[range].kind != nrrdKind3DMaskedSymMatrix)
    throw ImageIoError(path, "has no 3D-masked-symmetric-matrix axis");
  // Element index = sum over axes of index * stride, the first axis fastest.
  // The voxels run over the other (domain) axes in their file order, which
  // is the order ITK gives them.
  std::size_t stride[NRRD_DIM_MAX];
  std::size_t s = 1;
  for (unsigned a = 0; a < nrrd->dim; ++a) {
    stride[a] = s;
    s *= nrrd->axis[a].size;
  }
  std::size_t voxels = 1;
  for (unsigned a = 0; a < nrrd->dim; ++a)
    if (static_cast<int>(a) != range) voxels *= nrrd->axis[a].size;
  std::vector<float> confidence(voxels);
  std::size_t index[NRRD_DIM_MAX] = {};
  for (std::size_t v = 0; v < voxels; ++v) {
    std::size_t element = 0;  // component 0 along the range axis
    for (unsigned a = 0; a < nrrd->dim; ++a) element += index[a] * stride[a];
    confidence[v] = static_cast<float>(nrrdDLookup[nrrd->type](nrrd->data, element));
    for (unsigned a = 0; a < nrrd->dim; ++a) {  // next voxel: odometer over domain axes
      if (static_cast<int>(a) == range) continue;
      if (++index[a] < nrrd->axis[a].size) break;
      index[a] = 0;
    }
  }
  return confidence;
}

}  // namespace stvd::imaging::detail
