// stvd's imaging adapter without ITK, stvd::imaging: the supported API in one
// include (with the core's, stvd/stvd.hpp, which it builds on).
//
// Diffusion-MRI data as the propagation needs them: tensor component orders,
// file layouts and frames; the metric from diffusion tensors; tensor and
// scalar volumes in memory and tensors from arrays; masks, seeds and path
// targets; the files of a run; MRtrix images and streamline files (.tck,
// .trk, .vtk) through our own code; a metric sampled at arbitrary points;
// the declarations of the tensor input's, seeds' and targets' options.
// Reading NIfTI and NRRD files is the ITK file I/O, stvd/itk.hpp. The
// headers in stvd/imaging/detail/ are detail: they may change without notice.
#pragma once

#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_field.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/image_files.hpp"
#include "stvd/imaging/label_values.hpp"
#include "stvd/imaging/metric_sampling.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/imaging/run_files.hpp"
#include "stvd/imaging/scalar_image.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/seed_voxels.hpp"
#include "stvd/imaging/spherical_harmonics.hpp"
#include "stvd/imaging/streamline_io.hpp"
#include "stvd/imaging/symmetric_eigen.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/imaging/tensor_frame_check.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/imaging/tensor_layout.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/imaging/tensor_plausibility.hpp"
#include "stvd/imaging/tensor_volume.hpp"
