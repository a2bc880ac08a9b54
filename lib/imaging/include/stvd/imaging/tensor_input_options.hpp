// How to read a tensor file and make the metric, as the front ends take it
// (--tensor-order, --tensor-frame, --mask, --tensor-kind,
// --diffusion-metric, --max-anisotropy, --fa-threshold,
// --accept-implausible-tensors), declared once (stvd/front_end/option_declarations.hpp)
// with the defaults of TensorInputOptions and kDefaultMaxAnisotropy.
#pragma once

#include <vector>

#include "stvd/front_end/option_declarations.hpp"
#include "stvd/imaging/tensor_input.hpp"

namespace stvd::imaging {

/// The order of six tensor attributes per vertex or tetrahedron of a mesh
/// when none is stated (`stvd distance MESH.node --tensors node|ele`): FSL's,
/// the order of NRRD tensors.
inline constexpr TensorOrder kDefaultAttributeTensorOrder = TensorOrder::Fsl;

const std::vector<OptionDeclaration>& tensorInputOptionDeclarations();
/// The one among them with this flag (std::logic_error when there is none).
const OptionDeclaration& tensorInputOption(const std::string& flag);

/// The options the given ones make (defaults for the others); their
/// messages will be in the values' naming. Their combinations are checked
/// too (checkTensorInputOptions): OptionError.
TensorInputOptions tensorInputOptionsOf(const OptionValues& values);

}  // namespace stvd::imaging
