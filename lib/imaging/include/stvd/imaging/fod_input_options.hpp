// How the tool reads an FOD image and makes its cost (--fod-basis,
// --fod-frame, --fod-floor, --fod-power), declared once
// (stvd/front_end/option_declarations.hpp) with the defaults of
// FodCostOptions (docs/fod.md). `stvd distance` takes them, and
// stvd.fod_distance as fod_basis, fod_frame, fod_floor and fod_power.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "stvd/front_end/option_declarations.hpp"
#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_field.hpp"

namespace stvd::imaging {

const std::vector<OptionDeclaration>& fodInputOptionDeclarations();

/// The FOD options given on a command line. `read.basis` is empty when
/// --fod-basis was not given: then the input is no FOD image and the other
/// FOD options are refused (fodInputOptionsOf).
struct FodInputOptions {
  FodReadOptions read;
  FodCostOptions cost;
  bool given() const { return !read.basis.empty(); }
};

/// The options the given ones make; OptionError when --fod-frame,
/// --fod-floor or --fod-power come without --fod-basis.
FodInputOptions fodInputOptionsOf(const OptionValues& values);

}  // namespace stvd::imaging
