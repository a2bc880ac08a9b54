// The statistics file (--stats) of the geodesic subcommands: the run's
// command line, parameters, voxel counts, seeds, propagation and timings as
// JSON, in one layout for distance, path and connectivity, so that
// `stvd report` reads any of them.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "command_line.hpp"
#include "geodesic_options.hpp"
#include "memory_check.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/front_end/propagation_choice.hpp"

namespace stvd::tool {

/// What a statistics file records; pointers that are null leave their
/// sections out.
struct RunStatistics {
  std::string command;      ///< distance, path or connectivity
  std::string commandLine;  ///< as typed (commandLineText)
  std::string input;
  std::string output;
  /// Further outputs by role ("paths", "paths_table"), written as "outputs".
  std::vector<std::pair<std::string, std::string>> outputs;
  const PropagationChoice* choice = nullptr;
  double maxDistance = std::numeric_limits<double>::infinity();
  const TensorInputOptions* tensor = nullptr;
  const TensorInput* tensorInput = nullptr;
  imaging::MetricVoxelCounts counts;
  std::string seedLabels;  ///< --seeds
  std::string labels;      ///< --labels of connectivity
  std::string targetLabels;  ///< --targets of path (label regions)
  bool withUnreachableValue = false;
  float unreachableValue = 0.f;
  const std::vector<Seed>* seeds = nullptr;
  std::size_t labelSeedsLeftOut = 0;
  const PropagationResult* result = nullptr;  ///< also gives "distance_mm"
  const MemoryCheck* memory = nullptr;        ///< the check before the propagation
  /// The metric's parameters as `"name": value` JSON members, instead of
  /// the tensor file's and tensor metric's when not empty (an FOD input).
  std::vector<std::string> metricParameters;
  /// Sections of the command's own, as `"name": value` JSON members.
  std::vector<std::string> extraMembers;
  /// Seconds per phase, in order ("total" last).
  std::vector<std::pair<std::string, double>> seconds;
};

/// The members that the volume commands (distance, path, connectivity) fill
/// alike, from their options `o` (a PropagationChoice with `input`,
/// `output` and `tensor`; it and `input` must outlive the statistics).
template <class Options>
RunStatistics volumeRunStatistics(const std::string& command, const std::string& commandLine, const Options& o,
                                  const TensorInput& input, const imaging::MetricVoxelCounts& counts) {
  RunStatistics run;
  run.command = command;
  run.commandLine = commandLine;
  run.input = o.input;
  run.output = o.output;
  run.choice = &o;
  run.tensor = &o.tensor;
  run.tensorInput = &input;
  run.counts = counts;
  return run;
}

/// The JSON text of the statistics file, its "warnings" inputWarnings().
std::string statisticsJson(const RunStatistics& run);

/// The command line as one line a shell reads back (arguments quoted where
/// needed).
std::string commandLineText(int argc, char** argv);

/// Reached voxels, largest and median finite distance.
struct DistanceStatistics {
  std::size_t reached = 0;
  double maximum = 0.0;
  double median = 0.0;
};
DistanceStatistics summariseDistances(const std::vector<double>& distance);

}  // namespace stvd::tool
