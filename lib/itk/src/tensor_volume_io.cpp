// Reading and writing tensor volumes through ITK's image IO classes. The raw
// component buffers are used rather than itk::Image<DiffusionTensor3D>: it
// keeps ITK's tensor headers (and the Eigen copy they carry) out of stvd.
#include <itkMetaDataObject.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <utility>

#include "itk_io_support.hpp"
#include "nrrd_header.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/detail/image_output.hpp"
#include "stvd/imaging/detail/read_progress.hpp"
#include "stvd/imaging/image_files.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "written_files.hpp"

namespace stvd::imaging {
namespace {

std::string describeLayout(itk::ImageIOBase& io) {
  std::ostringstream s;
  s << io.GetNumberOfDimensions() << "D ";
  for (unsigned d = 0; d < io.GetNumberOfDimensions(); ++d) s << (d ? "x" : "") << io.GetDimensions(d);
  s << ", " << io.GetNumberOfComponents() << " component(s) per voxel ("
    << itk::ImageIOBase::GetPixelTypeAsString(io.GetPixelType()) << ")";
  return s.str();
}

Matrix3 transpose(const Matrix3& m) {
  return {m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]};
}

/// An MRtrix tensor image: X Y Z 6, as dwi2tensor writes it (components
/// D11 D22 D33 D12 D13 D23 along the scanner's RAS axes), or X Y Z 1 6 (any
/// number of axes of size 1 before the six volumes), as mrconvert makes it
/// from a NIfTI 5D tensor file.
TensorReadResult readMrtrixTensorVolume(const std::string& path, const TensorReadOptions& options,
                                        InterruptScope& progress) {
  // The conversion into tensors comes after the file's values: a step per
  // voxel, a sixth of the values.
  const GridGeometry grid = readMrtrixImageGrid(path);
  MrtrixImage image = detail::readMrtrixImage(path, progress, grid.voxelCount());
  const std::vector<std::size_t>& size = image.header.size;
  bool tensorShape = size.size() >= 4 && size.back() == 6;
  for (std::size_t a = 3; tensorShape && a + 1 < size.size(); ++a) tensorShape = size[a] == 1;
  if (!tensorShape) {
    std::string dim;
    for (std::size_t s : size) dim += (dim.empty() ? "" : ",") + std::to_string(s);
    throw ImageIoError(path, "not a tensor volume: an MRtrix tensor image has 6 volumes along its last axis "
                             "(dim X,Y,Z,6, or X,Y,Z,1,6 as mrconvert makes it from a NIfTI 5D file), this one "
                             "has dim " + dim);
  }
  TensorReadResult result;
  TensorFileInfo& info = result.info;
  info.layout = TensorFileLayout::MrtrixSixVolumes;
  info.order = resolveTensorOrder(path, info.layout, options.order);
  info.frameWasStated = options.frame.has_value();
  info.frame = options.frame.value_or(defaultTensorFrame(info.layout, info.order));
  info.componentType = image.header.datatype;
  result.volume.geometry = image.geometry;
  info.componentsToLps = info.frame == TensorFrame::Voxel ? mrtrixStoredVoxelAxes(image.header, image.geometry)
                                                          : componentFrameToLps(info, image.geometry);
  // The values are in logical order, axis 0 fastest: the axes of size 1
  // change nothing, and the six volumes follow one another.
  result.volume.tensors =
      detail::tensorsFromArray(image.values.data(), image.geometry.size,
                               oneVolumePerComponent(image.geometry.size, info.order), info.componentsToLps, progress,
                               2 * image.values.size());
  return result;
}

TensorReadResult readItkTensorVolume(const std::string& path, const TensorReadOptions& options,
                                     InterruptScope& progress);

}  // namespace

TensorReadResult readTensorVolume(const std::string& path, const TensorReadOptions& options,
                                  Interrupter* interrupter) {
  InterruptScope progress(interrupter, "reading tensors", 0);
  TensorReadResult result =
      isMrtrixImagePath(path) ? readMrtrixTensorVolume(path, options, progress) : readItkTensorVolume(path, options, progress);
  progress.finish();
  return result;
}

namespace {

TensorReadResult readItkTensorVolume(const std::string& path, const TensorReadOptions& options,
                                     InterruptScope& progress) {
  detail::OpenedImage image = detail::openImageForReading(path);
  itk::ImageIOBase::Pointer io = image.io;
  const std::string ioClass = io->GetNameOfClass();
  const unsigned dims = io->GetNumberOfDimensions();
  const unsigned components = io->GetNumberOfComponents();
  const bool tensorPixel = io->GetPixelType() == itk::IOPixelEnum::SYMMETRICSECONDRANKTENSOR;

  TensorReadResult result;
  TensorFileInfo& info = result.info;
  info.warnings = image.screened.warnings;
  info.componentType = itk::ImageIOBase::GetComponentTypeAsString(io->GetComponentType());
  // How the components sit in ITK's buffer: interleaved per voxel (true) or
  // one volume after the other (false).
  bool interleaved = true;
  TensorOrder bufferOrder = TensorOrder::Fsl;

  if (ioClass == "NrrdImageIO") {
    if (!(dims == 3 && components == 6 && tensorPixel))
      throw ImageIoError(path, "not a 3D tensor NRRD (kind 3D-symmetric-matrix or 3D-masked-symmetric-matrix "
                               "expected), found " + describeLayout(*io));
    const detail::NrrdTensorHeader header = detail::readNrrdTensorHeader(path);
    info.layout = header.masked ? TensorFileLayout::NrrdMaskedSymMatrix : TensorFileLayout::NrrdSymMatrix;
    info.order = resolveTensorOrder(path, info.layout, options.order);
    info.nrrdSpace = header.space;
    info.hasMeasurementFrame = header.hasMeasurementFrame;
    info.measurementFrameLps = multiply(header.spaceToLps, header.measurementFrame);
    // ITK hands the six tensor values over in NRRD's own order, xx xy xz yy yz zz.
    bufferOrder = TensorOrder::Fsl;
  } else if (ioClass == "NiftiImageIO") {
    // ITK drops the third axis of a 5D file of one slice (geometryOf()
    // takes it back from the header).
    const bool oneSlice = dims < 3 && image.screened.niftiDim[0] == 5 && image.screened.niftiDim[3] == 1;
    if ((dims == 3 || oneSlice) && components == 6 && tensorPixel) {
      info.layout = TensorFileLayout::NiftiSymMatrix5D;
      info.order = resolveTensorOrder(path, info.layout, options.order);
      // ITK reorders the standard's lower triangle into its own upper one.
      bufferOrder = TensorOrder::Fsl;
    } else if ((dims == 3 && components == 6) || (dims == 4 && components == 1 && io->GetDimensions(3) == 6) ||
               (dims == 5 && components == 1 && io->GetDimensions(3) == 1 && io->GetDimensions(4) == 6)) {
      // Six values per voxel without the SYMMATRIX intent: four dimensions
      // with six volumes, or five with the six along the fifth (as the 5D
      // layout, without its intent).
      info.layout = TensorFileLayout::NiftiSixVolumes;
      info.order = resolveTensorOrder(path, info.layout, options.order);
      bufferOrder = info.order;
      interleaved = dims == 3;
    } else if (dims == 4 && components == 1) {
      throw ImageIoError(path, "a 4D NIfTI tensor file needs 6 volumes (one per component), this one has " +
                                   std::to_string(io->GetDimensions(3)));
    } else if (components == 1) {
      throw ImageIoError(path, "is a scalar image (" + describeLayout(*io) + "), not a tensor volume");
    } else {
      throw ImageIoError(path, "not a tensor volume: expected 6 components per voxel, found " +
                                   describeLayout(*io));
    }
  } else {
    throw ImageIoError(path, std::string("unsupported format (") + ioClass + "); use NIfTI or NRRD");
  }
  info.frameWasStated = options.frame.has_value();
  info.frame = options.frame.value_or(defaultTensorFrame(info.layout, info.order));

  TensorVolume& volume = result.volume;
  volume.geometry = detail::geometryOf(image, path);
  const std::size_t n = volume.geometry.voxelCount();
  // Steps: the six values of every voxel, read by ITK in one call (done
  // when it returns), then a step per voxel of the conversion, then (a
  // masked NRRD) its confidence channel, read in one call.
  const bool confidenceToo = info.layout == TensorFileLayout::NrrdMaskedSymMatrix;
  progress.setTotal(6 * std::uint64_t(n) + n + (confidenceToo ? n : 0));
  const std::vector<float> values = detail::readAllComponents(image, path);
  progress.check(6 * std::uint64_t(n));
  if (values.size() != 6 * n)
    throw ImageIoError(path, "holds " + std::to_string(values.size()) + " values, expected 6 per voxel");

  // The same conversion as for arrays in memory (tensor_arrays.hpp).
  info.componentsToLps = componentFrameToLps(info, volume.geometry);
  const TensorComponentLayout layout = interleaved ? componentsPerVoxel(volume.geometry.size, bufferOrder)
                                                   : oneVolumePerComponent(volume.geometry.size, bufferOrder);
  volume.tensors = detail::tensorsFromArray(values.data(), volume.geometry.size, layout, info.componentsToLps,
                                            progress, 6 * std::uint64_t(n));

  if (confidenceToo) {
    const std::vector<float> confidence = detail::readNrrdConfidence(path);
    progress.check(8 * std::uint64_t(n));
    if (confidence.size() != n)
      throw ImageIoError(path, "confidence channel has " + std::to_string(confidence.size()) +
                                   " values for " + std::to_string(n) + " voxels");
    volume.mask.resize(n);
    // teem's convention: a voxel counts when its confidence is at least 0.5.
    for (std::size_t v = 0; v < n; ++v) volume.mask[v] = confidence[v] >= 0.5f ? 1 : 0;
  }
  return result;
}

}  // namespace

void writeTensorVolume(const std::string& path, const TensorVolume& volume,
                       const TensorWriteOptions& options) {
  const GridGeometry& g = volume.geometry;
  const std::size_t n = g.voxelCount();
  if (volume.tensors.size() != n)
    throw ImageIoError(path, "tensor count " + std::to_string(volume.tensors.size()) +
                                 " does not match the geometry's " + std::to_string(n) + " voxels");
  const bool nrrd = options.layout == TensorFileLayout::NrrdSymMatrix;
  if (options.layout == TensorFileLayout::NrrdMaskedSymMatrix)
    throw ImageIoError(path, "writing 3D-masked-symmetric-matrix NRRD is not supported");

  // Components in the file's frame: M^T T M for the matrix M that maps them to LPS.
  Matrix3 toLps;
  if (options.frame == TensorFrame::Voxel)
    toLps = voxelAxes(g);
  else
    toLps = nrrd ? Matrix3{1, 0, 0, 0, 1, 0, 0, 0, 1} : rasToLps();
  const Matrix3 fromLps = transpose(toLps);

  const bool mrtrix = options.layout == TensorFileLayout::MrtrixSixVolumes;
  const bool sixVolumes = options.layout == TensorFileLayout::NiftiSixVolumes || mrtrix;
  const TensorOrder order = sixVolumes ? options.order : TensorOrder::Fsl;
  std::vector<float> buffer(6 * n);
  float c[6];
  for (std::size_t v = 0; v < n; ++v) {
    componentsOfTensor(changeTensorFrame(volume.tensors[v], fromLps), order, c);
    for (int q = 0; q < 6; ++q) (sixVolumes ? buffer[v + n * q] : buffer[6 * v + q]) = c[q];
  }

  if (mrtrix != isMrtrixImagePath(path))
    throw ImageIoError(path, "the extension does not match the layout " + tensorFileLayoutName(options.layout));
  detail::writeAtomically(path, [&](const std::string& staging) {
    if (mrtrix) {
      writeMrtrixImage(staging, path, g, buffer, 6);
      detail::checkWrittenImage(staging, path, buffer);
      return;
    }
    itk::ImageIOBase::Pointer io =
        sixVolumes ? detail::createFloatWriter(staging, path, g, 1, itk::IOPixelEnum::SCALAR, 6)
                   : detail::createFloatWriter(staging, path, g, 6, itk::IOPixelEnum::SYMMETRICSECONDRANKTENSOR);
    const std::string ioClass = io->GetNameOfClass();
    if (nrrd != (ioClass == "NrrdImageIO"))
      throw ImageIoError(path, "the extension does not match the layout " + tensorFileLayoutName(options.layout));
    if (nrrd && options.frame == TensorFrame::Voxel) {
      // The measurement frame's columns are the index axes in LPS.
      std::vector<std::vector<double>> frame(3, std::vector<double>(3));
      for (int col = 0; col < 3; ++col)
        for (int r = 0; r < 3; ++r) frame[col][r] = toLps[3 * r + col];
      itk::EncapsulateMetaData<std::vector<std::vector<double>>>(io->GetMetaDataDictionary(),
                                                                 "NRRD_measurement frame", frame);
    }
    checkImageOutputCompanions(path);
    detail::writeFloatData(*io, path, buffer.data());
    detail::checkWrittenImage(staging, path, buffer);
  });
}

}  // namespace stvd::imaging
