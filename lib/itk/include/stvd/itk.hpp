// stvd's ITK file I/O, stvd::itk: the supported API in one include (with the
// imaging adapter's, stvd/imaging.hpp, and the core's, which it builds on).
//
// Tensor volumes, scalar and label images read from and written to NIfTI and
// NRRD files through ITK, and MRtrix images through the same functions; a
// tensor input read with its mask; a side input's grid read from its header
// alone and compared with the tensors' before its data. Every header is
// screened before ITK sees it, and every write is checked
// (docs/reliability.md).
#pragma once

#include "stvd/imaging.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/itk/itk_messages.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/tensor_input_io.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
