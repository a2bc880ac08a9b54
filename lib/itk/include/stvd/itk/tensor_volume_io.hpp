// Tensor volumes read and written as files: NIfTI and NRRD through ITK,
// MRtrix images through our own code (stvd/imaging/mrtrix_image.hpp), their
// tensors brought into and out of the LPS frame (stvd/imaging/
// tensor_volume.hpp describes the frames).
#pragma once

#include <string>

#include "stvd/imaging/tensor_volume.hpp"
#include "stvd/system/interrupter.hpp"

namespace stvd::imaging {

/// Reads a tensor volume from a .nii, .nii.gz, .nrrd, .nhdr, .mif, .mif.gz
/// or .mih file (MRtrix: X Y Z 6 or X Y Z 1 6, order mrtrix unless stated) and brings
/// its tensors into the LPS frame. The header is checked before the file's
/// data are read (see docs/reliability.md). A tensor with a NaN or infinite
/// component in the file is NaN in every component, whatever the format
/// (niftilib would have turned it into zeros). Throws ImageIoError with a
/// one-line message naming the file: unreadable, truncated or hostile file,
/// not a tensor layout (scalar image, wrong component count), a 4D NIfTI
/// without an order, an order that contradicts the file.
///
/// `interrupter` hears "reading tensors": 0 %; the file's values, which
/// ITK (NIfTI, NRRD) or our reader (the bytes of an MRtrix file) read in
/// one piece that cannot be cut, so that the next report comes when they
/// are in; then the decoding of MRtrix values and the conversion of the
/// components into tensors, at least every kDefaultInterruptInterval; 100 %.
/// When it asks to stop, Cancelled is thrown (nothing is returned).
TensorReadResult readTensorVolume(const std::string& path, const TensorReadOptions& options = {},
                                  Interrupter* interrupter = nullptr);

/// Writes `volume` (tensors in LPS) as float32 in the given layout, order
/// and frame, atomically and checked as writeScalarImage writes (see
/// scalar_image_io.hpp). The mask is not written. Throws ImageIoError.
void writeTensorVolume(const std::string& path, const TensorVolume& volume,
                       const TensorWriteOptions& options);

}  // namespace stvd::imaging
