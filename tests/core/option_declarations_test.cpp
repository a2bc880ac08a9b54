// Options declared once (stvd/front_end/option_declarations.hpp): the declarations of
// the core's options hold the library's own defaults, ranges and names, and
// the one checker gives one message form per problem, in the tool's flags
// or the Python package's keywords.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "stvd/cell_mesh/cell_mesh_propagation.hpp"
#include "stvd/front_end/mesh_options.hpp"
#include "stvd/front_end/path_tracing_options.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

/// The message of the OptionError that `check` throws; "" when none.
template <class Check>
std::string messageOf(Check check) {
  try {
    check();
  } catch (const OptionError& e) {
    return e.what();
  }
  return "";
}

std::string parseMessage(const std::string& flag, const std::string& text) {
  return messageOf([&] { parseOptionText(propagationOption(flag), text); });
}

TEST(OptionDeclarations, PropagationDefaultsAreTheLibrarysConstantsPerKindOfDomain) {
  const OptionDeclaration& k = propagationOption("--k");
  EXPECT_EQ(k.defaultFor(kDistanceCommand), OptionValue(static_cast<long long>(defaultMemoryDepth<VoxelGridDomain>())));
  EXPECT_EQ(k.defaultFor(kSurfaceDistanceCommand),
            OptionValue(static_cast<long long>(defaultMemoryDepth<SurfaceDomain>())));
  EXPECT_EQ(k.defaultFor(kTetMeshDistanceCommand),
            OptionValue(static_cast<long long>(defaultMemoryDepth<CellMeshDomain>())));
  EXPECT_EQ(optionDefaultText(k, kSurfaceDistanceCommand), std::to_string(kDefaultSurfaceMemoryDepth));
  EXPECT_EQ(optionRangeText(k), "1.." + std::to_string(kMaxMemoryDepth));
  EXPECT_EQ(optionRangeText(propagationOption("--steiner")), "1.." + std::to_string(kMaxSteinerPoints));
  const PropagationChoice choice;
  EXPECT_EQ(optionDefaultText(propagationOption("--chain-measure"), kPathCommand),
            chainMeasureName(kDefaultChainMeasure));
  EXPECT_EQ(optionDefaultText(propagationOption("--method"), kDistanceCommand), methodName(choice));
  EXPECT_EQ(optionDefaultText(propagationOption("--stencil"), kDistanceCommand), choice.stencil);
  EXPECT_EQ(optionDefaultText(propagationOption("--domain-connectivity"), kDistanceCommand),
            std::to_string(static_cast<int>(choice.connectivity)));
  EXPECT_EQ(propagationOption("--unreachable-value").defaultFor(kDistanceCommand), OptionValue(kDefaultUnreachableValue));
  const PathTracingOptions tracing;
  const OptionDeclaration* step = findOption(pathTracingOptionDeclarations(), "--step");
  ASSERT_NE(step, nullptr);
  EXPECT_EQ(step->defaultFor(kPathCommand), OptionValue(tracing.stepFraction));
}

TEST(OptionDeclarations, EveryChoiceIsOneTheLibraryAccepts) {
  for (const OptionChoice& c : propagationOption("--stencil").choices) EXPECT_NO_THROW(Stencil::byName(c.name));
  for (const OptionChoice& c : propagationOption("--domain-connectivity").choices) {
    PropagationChoice choice;
    setDomainConnectivity(choice, c.name);
    EXPECT_EQ(static_cast<int>(choice.connectivity), std::stoi(c.name));
  }
  for (const OptionChoice& c : propagationOption("--chain-measure").choices) {
    PropagationChoice choice;
    setChainMeasure(choice, c.name);
    EXPECT_EQ(chainMeasureName(choice.chainMeasure), c.name);
  }
  for (const OptionChoice& c : propagationOption("--method").choices) {
    PropagationChoice choice;
    setMethod(choice, c.name);
    EXPECT_EQ(methodName(choice), c.name);
  }
}

TEST(OptionDeclarations, EveryDefaultAndChoiceAppearsInTheHelp) {
  for (const auto* table : {&propagationOptionDeclarations(), &pathTracingOptionDeclarations(),
                            &meshOptionDeclarations(), &regionConnectivityOptionDeclarations()})
    for (const OptionDeclaration& o : *table)
      for (const OptionCommand command : {kDistanceCommand, kPathCommand, kConnectivityCommand,
                                          kSurfaceDistanceCommand, kTetMeshDistanceCommand}) {
        if (!o.takes(command)) continue;
        const std::string help = optionHelpText(o, command), byDefault = optionDefaultText(o, command);
        EXPECT_EQ(help.find('{'), std::string::npos) << o.flag << ": " << help;
        for (const OptionChoice& c : o.choices) EXPECT_NE(help.find(c.name), std::string::npos) << o.flag;
        if (byDefault.empty()) continue;
        const bool stated = help.find("(default " + byDefault) != std::string::npos ||
                            help.find("(default: " + byDefault) != std::string::npos ||
                            help.find(byDefault + " (default") != std::string::npos;
        EXPECT_TRUE(stated) << o.flag << " does not state its default " << byDefault << ": " << help;
      }
}

TEST(OptionDeclarations, OneMessageFormPerProblemInFlagsOrKeywords) {
  EXPECT_EQ(parseMessage("--k", "x"), "--k: 'x' is not an integer");
  EXPECT_EQ(parseMessage("--k", "3.5"), "--k: '3.5' is not an integer");
  EXPECT_EQ(parseMessage("--k", "17"), "--k must be between 1 and 16");
  EXPECT_EQ(parseMessage("--max-distance", "0"), "--max-distance must be positive");
  EXPECT_EQ(parseMessage("--max-distance", "inf"), "--max-distance: 'inf' is not a number");
  EXPECT_EQ(parseMessage("--method", "fast"), "--method: 'fast' is not one of stvd, dijkstra, lanthier");
  EXPECT_EQ(parseMessage("--unreachable-value", "1e300"),
            "--unreachable-value: '1e300' does not fit in a float32 map (magnitude at most 3.4e38)");
  EXPECT_TRUE(std::isnan(std::get<double>(parseOptionText(propagationOption("--unreachable-value"), "nan"))));
  const OptionDeclaration* step = findOption(pathTracingOptionDeclarations(), "--step");
  EXPECT_EQ(messageOf([&] { parseOptionText(*step, "1.5"); }), "--step must be in (0, 1]");
  const OptionDeclaration* anisotropy = findOption(meshOptionDeclarations(), "--anisotropy");
  EXPECT_EQ(messageOf([&] { parseOptionText(*anisotropy, "0.5"); }), "--anisotropy must be at least 1");

  // The Python package's keywords: the same checks, in its own names.
  const auto keywordMessage = [](const OptionDeclaration& o, OptionValue value) {
    return messageOf([&] { checkOptionValue(o, std::move(value), OptionNaming::Keywords); });
  };
  EXPECT_EQ(keywordMessage(propagationOption("--k"), 17LL), "k must be between 1 and 16");
  EXPECT_EQ(keywordMessage(propagationOption("--chain-measure"), std::string("mean")),
            "chain_measure: 'mean' is not one of segment, projection, largest");
  EXPECT_EQ(keywordMessage(propagationOption("--max-distance"), std::nan("")), "max_distance: 'nan' is not a number");
  // max_distance=math.inf means no limit, as None does.
  EXPECT_EQ(keywordMessage(propagationOption("--max-distance"), HUGE_VAL), "");
  const OptionDeclaration* metric = findOption(meshOptionDeclarations(), "--metric");
  EXPECT_EQ(messageOf([&] { parseOptionText(*metric, "field"); }),
            "--metric: 'field' is not one of isotropic, curvature, field:FILE, tensors:FILE, face-tensors:FILE, scale:FILE");
  EXPECT_EQ(std::get<std::string>(parseOptionText(*metric, "field:f.txt")), "field:f.txt");
  EXPECT_EQ(keywordMessage(*metric, std::string("field:f.txt")),
            "metric: 'field:f.txt' is not one of isotropic, curvature, field, tensors, face-tensors, scale");
  EXPECT_EQ(keywordMessage(*metric, std::string("field")), "");
}

TEST(OptionDeclarations, CombinationsAreRefusedInTheFrontEndsNames) {
  PropagationChoice dijkstra;
  dijkstra.naming = OptionNaming::Keywords;
  setMethod(dijkstra, "dijkstra");
  setMemoryDepth(dijkstra, 3);
  EXPECT_EQ(messageOf([&] { checkPropagationChoice(dijkstra, true); }), "k applies to method='stvd' only");
  dijkstra.naming = OptionNaming::Flags;
  EXPECT_EQ(messageOf([&] { checkPropagationChoice(dijkstra, true); }), "--k applies to --method stvd only");

  OptionValues values(OptionNaming::Keywords);
  values.set(propagationOption("--method"), std::string("lanthier"));
  EXPECT_EQ(messageOf([&] { checkPropagationChoice(propagationChoiceOf(values), true); }),
            "method='lanthier' needs steiner=M, the Steiner points per cube edge (1..16; try 2)");
  OptionValues corners(OptionNaming::Keywords);
  corners.set(propagationOption("--domain-connectivity"), std::string("26"));
  corners.set(propagationOption("--stencil"), std::string("18"));
  EXPECT_EQ(messageOf([&] { checkPropagationChoice(propagationChoiceOf(corners), true); }),
            "domain_connectivity=26 joins voxels that touch at a corner, which the 18-neighbour stencil cannot step "
            "between; use stencil='26' or larger");
  EXPECT_EQ(messageOf([] { checkSurfaceMetricChoice("curvature", false, OptionNaming::Keywords); }),
            "metric='curvature' needs anisotropy=G");
  EXPECT_EQ(messageOf([] { checkSurfaceMetricChoice("field:f.txt", false, OptionNaming::Flags); }),
            "--metric field:f.txt needs --anisotropy G");
}

TEST(OptionDeclarations, TheGivenOptionsMakeTheChoice) {
  OptionValues values;
  values.setChecked(propagationOption("--k"), parseOptionText(propagationOption("--k"), "4"));
  values.setChecked(propagationOption("--chain-measure"), std::string("largest"));
  values.setChecked(propagationOption("--domain-connectivity"), std::string("18"));
  values.setChecked(propagationOption("--no-memory-check"), true);
  const PropagationChoice choice = propagationChoiceOf(values);
  EXPECT_EQ(choice.k, 4);
  EXPECT_EQ(choice.chainMeasure, ChainMeasure::LargestEdgeNorm);
  EXPECT_TRUE(choice.chainMeasureGiven);
  EXPECT_EQ(choice.connectivity, VoxelConnectivity::Edges);
  EXPECT_FALSE(choice.memoryCheck);
  EXPECT_FALSE(choice.stencilGiven);
  OptionValues threads;
  threads.set(*findOption(regionConnectivityOptionDeclarations(), "--threads"), 3LL);
  EXPECT_EQ(regionThreadsOf(threads), 3u);
  EXPECT_EQ(regionThreadsOf(OptionValues()), 0u);  // one per core
}

}  // namespace
}  // namespace stvd
