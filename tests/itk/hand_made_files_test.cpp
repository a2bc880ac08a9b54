// Files written byte by byte by the tests, in every layout and frame, that
// all encode one constant metric with a known exact distance: the readers
// must bring each of them to the same tensors in LPS, and the propagation
// must then give the exact distances.
#include <gtest/gtest.h>

#include "known_field.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd::imaging {
namespace {

using stvd::testing::HandGeometry;
using stvd::testing::KnownField;
using stvd::testing::NiftiTensorLayout;
using stvd::testing::relativeDifference;

class HandMadeFiles : public stvd::testing::ScratchFolderTest {
 protected:
  KnownField field;

  std::string nrrd(const std::string& name, const std::string& space, const SymTensor3& stored,
                   const Matrix3* frame, std::vector<float> confidence = {}) {
    const std::string file = path(name);
    stvd::testing::writeTensorNrrdByHand(file, field.geometry, space,
                                         std::vector<SymTensor3>(field.voxelCount(), stored), frame, confidence);
    return file;
  }
  std::string nifti(const std::string& name, NiftiTensorLayout layout, const SymTensor3& stored, TensorOrder order) {
    float c[6];
    componentsOfTensor(stored, order, c);
    std::array<float, 6> perVoxel;
    std::copy(c, c + 6, perVoxel.begin());
    const std::string file = path(name);
    stvd::testing::writeNiftiByHand(file, field.geometry, layout,
                                    std::vector<std::array<float, 6>>(field.voxelCount(), perVoxel));
    return file;
  }

  void expectKnownField(const TensorReadResult& read, double tolerance = 2e-6) {
    const GridGeometry expected = field.geometry.grid();
    EXPECT_EQ(read.volume.geometry.size, expected.size);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(read.volume.geometry.spacing[i], expected.spacing[i], 1e-5);
      EXPECT_NEAR(read.volume.geometry.origin[i], expected.origin[i], 1e-4);
    }
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(read.volume.geometry.direction[i], expected.direction[i], 1e-6);
    const SymTensor3 lps = field.lpsMetric();
    for (std::size_t v : {std::size_t(0), field.voxelCount() / 2, field.voxelCount() - 1})
      EXPECT_LT(relativeDifference(read.volume.tensors[v], lps), tolerance) << "voxel " << v;
  }

  /// Distances from the centre with the file's tensors taken as the metric.
  std::vector<double> distances(const TensorReadResult& read, Method method, int k = 3) {
    MetricOptions options;
    options.kind = TensorKind::Metric;
    options.maxAnisotropy = 1e6;
    MetricFromTensors built = buildMetric(read.volume.tensors, read.volume.mask, options);
    const VoxelGridDomain domain(read.volume.geometry, Stencil::full26(), built.inDomain);
    const RiemannianMetric metric(std::move(built.metric), &built.inDomain);
    PropagationOptions propagation;
    propagation.method = method;
    propagation.k = k;
    const auto c = field.centre();
    return propagate(domain, metric, {domain.vertexAt(c[0], c[1], c[2])}, propagation).distance;
  }

  /// Worst relative error on the stencil lines, and the largest relative
  /// amount by which any voxel falls below the exact distance.
  std::pair<double, double> errors(const std::vector<double>& d) {
    double onLines = 0.0, below = 0.0;
    for (const auto& p : field.voxelsOnStencilLines()) {
      const double exact = field.exactDistance(field.centre(), p);
      onLines = std::max(onLines, std::abs(d[field.linear(p)] - exact) / exact);
    }
    for (int k = 0; k < field.geometry.size[2]; ++k)
      for (int j = 0; j < field.geometry.size[1]; ++j)
        for (int i = 0; i < field.geometry.size[0]; ++i) {
          const std::array<int, 3> p{i, j, k};
          const double exact = field.exactDistance(field.centre(), p);
          if (exact > 0) below = std::max(below, (exact - d[field.linear(p)]) / exact);
        }
    return {onLines, below};
  }
};

TEST_F(HandMadeFiles, NrrdWithAMeasurementFrameGivesTheMetricInLps) {
  const Matrix3 frame = field.measurementFrameLps;
  const TensorReadResult read =
      readTensorVolume(nrrd("mf.nrrd", "left-posterior-superior", field.measurementFrameMetric(), &frame));
  EXPECT_EQ(read.info.layout, TensorFileLayout::NrrdSymMatrix);
  EXPECT_EQ(read.info.frame, TensorFrame::World);
  EXPECT_TRUE(read.info.hasMeasurementFrame);
  expectKnownField(read);
}

TEST_F(HandMadeFiles, NrrdInRasSpaceGivesTheSameGridAndTensorsInLps) {
  // Geometry and measurement frame are written in RAS coordinates; the
  // stored components (in the measurement frame) are the same numbers.
  const Matrix3 frame = field.measurementFrameLps;
  const TensorReadResult read =
      readTensorVolume(nrrd("ras.nrrd", "right-anterior-superior", field.measurementFrameMetric(), &frame));
  EXPECT_EQ(read.info.nrrdSpace, "right-anterior-superior");
  expectKnownField(read);
}

TEST_F(HandMadeFiles, NrrdInLasSpaceGivesTheSameGridAndTensorsInLps) {
  // Left-anterior-superior differs from LPS in y alone. ITK 5.2 reads such a
  // header as if x were flipped (its NrrdImageIO's LAS case), which mirrors
  // the grid; stvd reads it as the NRRD format defines it.
  const Matrix3 frame = field.measurementFrameLps;
  const TensorReadResult read =
      readTensorVolume(nrrd("las.nrrd", "left-anterior-superior", field.measurementFrameMetric(), &frame));
  EXPECT_EQ(read.info.nrrdSpace, "left-anterior-superior");
  expectKnownField(read);
  EXPECT_EQ(readImageGrid(path("las.nrrd")).origin, read.volume.geometry.origin);
}

TEST_F(HandMadeFiles, NrrdWithoutAMeasurementFrameHasItsComponentsInItsSpace) {
  const TensorReadResult lps = readTensorVolume(nrrd("lps.nrrd", "left-posterior-superior", field.lpsMetric(), nullptr));
  EXPECT_FALSE(lps.info.hasMeasurementFrame);
  expectKnownField(lps);
  const TensorReadResult ras = readTensorVolume(nrrd("ras.nrrd", "right-anterior-superior", field.rasMetric(), nullptr));
  expectKnownField(ras);
}

TEST_F(HandMadeFiles, NrrdReadInTheVoxelFrameIgnoresTheMeasurementFrame) {
  const Matrix3 frame = field.measurementFrameLps;
  const std::string voxelComponents =
      nrrd("voxel.nrrd", "left-posterior-superior", field.voxelFrameMetric, &frame);
  expectKnownField(readTensorVolume(voxelComponents, {std::nullopt, TensorFrame::Voxel}));
  // The same file read in its default (world) frame is another field.
  const TensorReadResult world = readTensorVolume(voxelComponents);
  EXPECT_GT(relativeDifference(world.volume.tensors[0], field.lpsMetric()), 0.05);
}

TEST_F(HandMadeFiles, MaskedNrrdTurnsTheConfidenceChannelIntoAMask) {
  const Matrix3 frame = field.measurementFrameLps;
  std::vector<float> confidence(field.voxelCount(), 1.f);
  confidence[0] = 0.f;
  confidence[1] = 0.49f;
  confidence[2] = 0.5f;
  const TensorReadResult read = readTensorVolume(
      nrrd("masked.nrrd", "left-posterior-superior", field.measurementFrameMetric(), &frame, confidence));
  EXPECT_EQ(read.info.layout, TensorFileLayout::NrrdMaskedSymMatrix);
  expectKnownField(read);
  ASSERT_EQ(read.volume.mask.size(), field.voxelCount());
  EXPECT_EQ(read.volume.mask[0], 0);
  EXPECT_EQ(read.volume.mask[1], 0);
  EXPECT_EQ(read.volume.mask[2], 1);
  EXPECT_EQ(read.volume.mask[3], 1);
}

TEST_F(HandMadeFiles, NiftiSymMatrixInTheVoxelFrameGivesTheMetricInLps) {
  const TensorReadResult read =
      readTensorVolume(nifti("sym.nii", NiftiTensorLayout::SymMatrix5D, field.voxelFrameMetric, TensorOrder::Lower));
  EXPECT_EQ(read.info.layout, TensorFileLayout::NiftiSymMatrix5D);
  EXPECT_EQ(read.info.frame, TensorFrame::Voxel);
  expectKnownField(read);
}

TEST_F(HandMadeFiles, NiftiSixVolumesInEveryOrderAndFrame) {
  struct Case {
    TensorOrder order;
    TensorFrame frame;
    SymTensor3 stored;
  };
  for (const Case& c : {Case{TensorOrder::Fsl, TensorFrame::Voxel, field.voxelFrameMetric},
                        Case{TensorOrder::Fsl, TensorFrame::World, field.rasMetric()},
                        Case{TensorOrder::Mrtrix, TensorFrame::World, field.rasMetric()},
                        Case{TensorOrder::Mrtrix, TensorFrame::Voxel, field.voxelFrameMetric},
                        Case{TensorOrder::Lower, TensorFrame::Voxel, field.voxelFrameMetric}}) {
    SCOPED_TRACE(tensorOrderName(c.order) + " " + tensorFrameName(c.frame));
    const std::string file = nifti("six_" + tensorOrderName(c.order) + "_" + tensorFrameName(c.frame) + ".nii",
                                   NiftiTensorLayout::SixVolumes4D, c.stored, c.order);
    const TensorReadResult read = readTensorVolume(file, {c.order, c.frame});
    EXPECT_EQ(read.info.layout, TensorFileLayout::NiftiSixVolumes);
    expectKnownField(read);
  }
}

TEST_F(HandMadeFiles, MrtrixOrderDefaultsToTheWorldFrame) {
  const std::string file = nifti("mrtrix.nii", NiftiTensorLayout::SixVolumes4D, field.rasMetric(), TensorOrder::Mrtrix);
  const TensorReadResult read = readTensorVolume(file, {TensorOrder::Mrtrix, std::nullopt});
  EXPECT_EQ(read.info.frame, TensorFrame::World);
  EXPECT_FALSE(read.info.frameWasStated);
  expectKnownField(read);
}

TEST_F(HandMadeFiles, Nifti5DWithoutTheSymMatrixIntentNeedsAnOrder) {
  const std::string file =
      nifti("vector5d.nii", NiftiTensorLayout::SixVector5DNoIntent, field.voxelFrameMetric, TensorOrder::Mrtrix);
  EXPECT_THROW(readTensorVolume(file), ImageIoError);
  const TensorReadResult read = readTensorVolume(file, {TensorOrder::Mrtrix, TensorFrame::Voxel});
  EXPECT_EQ(read.info.layout, TensorFileLayout::NiftiSixVolumes);
  expectKnownField(read);
}

TEST_F(HandMadeFiles, DistancesFromTheMeasurementFrameNrrdAreExact) {
  const Matrix3 frame = field.measurementFrameLps;
  const TensorReadResult read =
      readTensorVolume(nrrd("mf.nrrd", "left-posterior-superior", field.measurementFrameMetric(), &frame));
  for (Method method : {Method::Dijkstra, Method::ShortTermVectorDijkstra}) {
    const auto [onLines, below] = errors(distances(read, method));
    EXPECT_LT(onLines, 1e-5) << "exact along the stencil lines";
    EXPECT_LT(below, 1e-5) << "never shorter than the exact distance";
  }
}

TEST_F(HandMadeFiles, DistancesAgreeAcrossAllEncodingsOfTheField) {
  // Dijkstra: its distances depend continuously on the tensors, which the
  // encodings reproduce to single precision. (STVD's do not: a rounding
  // difference can break a tie between two predecessors differently and
  // change the chain, hence the distance off the stencil lines.)
  const Matrix3 frame = field.measurementFrameLps;
  const std::vector<double> reference = distances(
      readTensorVolume(nrrd("mf.nrrd", "right-anterior-superior", field.measurementFrameMetric(), &frame)),
      Method::Dijkstra);
  const std::vector<double> fromNifti = distances(
      readTensorVolume(nifti("sym.nii", NiftiTensorLayout::SymMatrix5D, field.voxelFrameMetric, TensorOrder::Lower)),
      Method::Dijkstra);
  const std::vector<double> fromMrtrix = distances(
      readTensorVolume(nifti("mrtrix.nii", NiftiTensorLayout::SixVolumes4D, field.rasMetric(), TensorOrder::Mrtrix),
                       {TensorOrder::Mrtrix, std::nullopt}),
      Method::Dijkstra);
  double worst = 0.0;
  for (std::size_t v = 0; v < reference.size(); ++v) {
    if (reference[v] == 0.0) continue;
    worst = std::max(worst, std::abs(fromNifti[v] - reference[v]) / reference[v]);
    worst = std::max(worst, std::abs(fromMrtrix[v] - reference[v]) / reference[v]);
  }
  EXPECT_LT(worst, 1e-5);
}

TEST_F(HandMadeFiles, IgnoringTheMeasurementFrameChangesTheDistances) {
  const Matrix3 frame = field.measurementFrameLps;
  const TensorReadResult wrong = readTensorVolume(
      nrrd("mf.nrrd", "left-posterior-superior", field.measurementFrameMetric(), &frame),
      {std::nullopt, TensorFrame::Voxel});
  const auto [onLines, below] = errors(distances(wrong, Method::Dijkstra));
  EXPECT_GT(onLines, 0.05);
}

}  // namespace
}  // namespace stvd::imaging
