// What the volume commands (distance, path, connectivity) share on FOD
// images (--fod-basis; docs/fod.md): the options a run on an FOD image
// refuses, the reading of the image and its mask, the table of the
// convexified norm F* and the statistics' description of the metric.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "stvd/imaging/fod_field.hpp"
#include "stvd/imaging/fod_input_options.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/fod_segment_norm.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/system/interrupter.hpp"

namespace stvd::tool {

/// Refuses (usage error) what a run on an FOD image cannot take: the
/// tensor file's options other than --mask, and a stencil other than 6,
/// 18 or 26 (F* is tabulated along the 26 neighbour directions).
void checkFodRunOptions(const OptionValues& values, const std::string& stencil);

/// An FOD image read for a run: the field, its grid (and the mask) as the
/// seeds' and labels' readers take a tensor input's, the domain.
struct FodInput {
  imaging::FodField fod;
  TensorInput grid;
  std::vector<std::uint8_t> inDomain;
  imaging::MetricVoxelCounts counts;
};

/// Reads `path` with `options` (lmax 4 to 12: six coefficients are a
/// tensor image's) and the mask at `maskPath` (empty: none) on its grid;
/// NothingToCompute when the domain is empty.
FodInput readFodInput(const std::string& path, const imaging::FodInputOptions& options, const std::string& maskPath);

/// The table of F* along the 26 neighbour directions of the domain's
/// voxels, and what it cost.
struct FodTable {
  imaging::FodStencilMetric metric;  ///< Dijkstra's: F* along the 26 neighbour directions
  /// STVD's and Lanthier's, when asked for: F* along the lattice directions
  /// of order 2, interpolated between them (docs/fod.md, "STVD and Lanthier").
  std::optional<imaging::FodSegmentMetric> segments;
  std::size_t directions = 0;  ///< sampling directions of the unit ball
  double seconds = 0.0;        ///< wall time
  double cpuSeconds = 0.0;     ///< the process's CPU time, all threads
  unsigned threads = 1;
};
/// `progress` (may be null) sees the table's blocks and may stop it
/// (Cancelled); `segments`: the segment metric instead of the 26 directions.
FodTable makeFodTable(const FodInput& input, const imaging::FodCostOptions& cost, unsigned threads,
                      Interrupter* progress = nullptr, bool segments = false);

/// The metric's parameters for RunStatistics::metricParameters ("metric":
/// "fod", the basis as resolved and as given, frame, lmax, floor, power,
/// directions, norm).
std::vector<std::string> fodMetricParameters(const FodInput& input, const imaging::FodInputOptions& options,
                                             const FodTable& table);
/// The "fod_precomputation" member of the statistics.
std::string fodPrecomputationMember(const FodInput& input, const FodTable& table);
/// "Read FILE (FOD, lmax 8, basis B in the F frame): NX x NY x NZ voxels
/// of ... mm, orientation XYZ. Cost: ... tabulated in S s (C s CPU on N
/// threads)", the opening of the summary paragraphs.
std::string fodInputText(const std::string& path, const FodInput& input, const imaging::FodInputOptions& options,
                         const FodTable& table);

/// One line for a file the tensor reader refused that reads as an FOD
/// image: its basis must be stated. Empty when it is no FOD image either.
std::string fodWithoutBasisMessage(const std::string& path);

}  // namespace stvd::tool
