// The tensor-file and seed options' declarations (stvd/itk/
// tensor_input_options.hpp, seed_options.hpp) hold the imaging adapter's
// own names and defaults, and their messages follow the front end's naming.
#include <gtest/gtest.h>

#include <string>

#include "stvd/errors.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/imaging/tensor_plausibility.hpp"

namespace stvd::imaging {
namespace {

TEST(TensorInputOptions, ChoicesAndAliasesAreTheNamesTheReaderAccepts) {
  const OptionDeclaration& order = tensorInputOption("--tensor-order");
  for (const OptionChoice& c : order.choices) {
    ASSERT_TRUE(parseTensorOrder(c.name).has_value()) << c.name;
    EXPECT_EQ(tensorOrderName(*parseTensorOrder(c.name)), c.name);
    EXPECT_NE(c.help.find(tensorOrderComponents(*parseTensorOrder(c.name))), std::string::npos);
  }
  for (const auto& [alias, name] : order.aliases) EXPECT_EQ(parseTensorOrder(alias), parseTensorOrder(name)) << alias;
  for (const OptionChoice& c : tensorInputOption("--tensor-frame").choices)
    EXPECT_TRUE(parseTensorFrame(c.name).has_value()) << c.name;
  for (const OptionChoice& c : tensorInputOption("--tensor-kind").choices)
    EXPECT_TRUE(parseTensorKind(c.name).has_value()) << c.name;
  for (const OptionChoice& c : tensorInputOption("--diffusion-metric").choices)
    EXPECT_TRUE(parseDiffusionMetric(c.name).has_value()) << c.name;
}

TEST(TensorInputOptions, DefaultsAreTheAdaptersConstants) {
  const TensorInputOptions defaults;
  EXPECT_EQ(optionDefaultText(tensorInputOption("--tensor-kind"), kDistanceCommand), tensorKindName(defaults.metric.kind));
  EXPECT_EQ(optionDefaultText(tensorInputOption("--diffusion-metric"), kDistanceCommand),
            diffusionMetricName(defaults.metric.diffusionMetric));
  EXPECT_EQ(tensorInputOption("--max-anisotropy").defaultFor(kDistanceCommand), OptionValue(kDefaultMaxAnisotropy));
  EXPECT_EQ(optionDefaultText(tensorInputOption("--tensor-order"), kTetMeshDistanceCommand),
            tensorOrderName(kDefaultAttributeTensorOrder));
  EXPECT_EQ(optionDefaultText(tensorInputOption("--tensor-order"), kDistanceCommand), "");  // must be stated
  EXPECT_NE(optionHelpText(tensorInputOption("--accept-implausible-tensors"), kDistanceCommand)
                .find(std::to_string(static_cast<int>(100 * kMaxNotPositiveDefiniteShare + 0.5)) + " %"),
            std::string::npos);
}

TEST(TensorInputOptions, TheGivenOptionsMakeTheReadersOptionsAndSpeakTheFrontEndsNames) {
  OptionValues values(OptionNaming::Keywords);
  values.set(tensorInputOption("--tensor-order"), std::string("upper"));
  values.set(tensorInputOption("--tensor-kind"), std::string("metric"));
  const TensorInputOptions options = tensorInputOptionsOf(values);
  EXPECT_EQ(options.order, TensorOrder::Fsl);
  EXPECT_EQ(options.metric.kind, TensorKind::Metric);
  // The reader checks the combination too, so that every front end that
  // reads these options (distance, path, connectivity, Python) refuses it.
  values.set(tensorInputOption("--fa-threshold"), 0.2);
  try {
    tensorInputOptionsOf(values);
    ADD_FAILURE() << "an FA threshold on metric tensors was accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "fa_threshold applies to tensor_kind='diffusion' only");
  }
  TensorInputOptions metricWithThreshold = options;
  metricWithThreshold.metric.faThreshold = 0.2;
  EXPECT_THROW(checkTensorInputOptions(metricWithThreshold), OptionError);
  try {
    values.set(tensorInputOption("--max-anisotropy"), 0.5);
    ADD_FAILURE() << "a cap below 1 was accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "max_anisotropy must be at least 1");
  }
  TensorInputOptions flags;
  try {
    setTensorFrame(flags, "scanner");
    ADD_FAILURE() << "an unknown frame was accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "--tensor-frame: 'scanner' is not one of voxel, world");
  }
}

TEST(SeedOptions, MissingSeedsAndTargetsAreNamedAsTheFrontEndNamesThem) {
  EXPECT_EQ(noSeedMessage(OptionNaming::Flags), "no seed: add --seed-voxel I,J,K, --seed-point X,Y,Z or --seeds LABELS");
  EXPECT_EQ(noSeedMessage(OptionNaming::Keywords), "no seed: add seeds=, seed_points= or seed_labels=");
  EXPECT_EQ(noTargetMessage(OptionNaming::Flags),
            "no target: add --target-voxel I,J,K, --target-point X,Y,Z or --targets LABELS");
  OptionValues values;
  const OptionDeclaration& voxel = *findOption(seedOptionDeclarations(), "--seed-voxel");
  values.setChecked(voxel, parseOptionText(voxel, "1, 2,3"));
  values.setChecked(voxel, parseOptionText(voxel, "4,5,6"));
  EXPECT_EQ(voxelsOf(values, "--seed-voxel"), (std::vector<std::array<int, 3>>{{1, 2, 3}, {4, 5, 6}}));
  try {
    parseOptionText(voxel, "55,54");
    ADD_FAILURE();
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "--seed-voxel: '55,54' is not three comma-separated numbers");
  }
}

}  // namespace
}  // namespace stvd::imaging
