// The ITK bridge (stvd/itk/bridge.hpp) against the tool: an image read by
// ITK, with its frame stated, gives exactly the tensors, and the filter
// exactly the distance map, that `stvd distance` gives from the file; the
// NRRD measurement frame is read by columns and the NRRD space flipped to
// LPS; an image whose region does not start at index 0 keeps its place in
// space; the filter's progress runs from 0 to 1 and an abort leaves no map.
#include <gtest/gtest.h>
#include <itkCommand.h>
#include <itkExtractImageFilter.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "stvd/itk.hpp"
#include "stvd/itk/bridge.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

using TensorImage = itk::Image<itk::DiffusionTensor3D<float>, 3>;
using MaskImage = itk::Image<unsigned char, 3>;
using imaging::GeodesicDistanceImageFilter;
using imaging::ItkDistanceImage;
using imaging::ItkTensorFrame;

template <class TImage>
typename TImage::Pointer readWithItk(const std::string& path) {
  auto reader = itk::ImageFileReader<TImage>::New();
  reader->SetFileName(path);
  reader->Update();
  return reader->GetOutput();
}

bool sameBits(const SymTensor3& a, const SymTensor3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

class ItkBridge : public ScratchFolderTest {
 protected:
  /// `stvd distance` on `file` with `arguments`, its map read back.
  std::vector<float> toolDistances(const std::string& file, std::vector<std::string> arguments) {
    arguments.insert(arguments.begin(), {"distance", file, "-o", path("tool.nii.gz"), "-q"});
    const ToolRun run = runTool(arguments);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    return imaging::readScalarImage(path("tool.nii.gz")).values;
  }
};

TEST_F(ItkBridge, TheFiltersMapOfTheBrainIsTheToolsBitForBit) {
  const TensorImage::Pointer tensors = readWithItk<TensorImage>(sampleFile("dti_tensor_dipy5d.nii.gz"));
  const MaskImage::Pointer mask = readWithItk<MaskImage>(sampleFile("dti_mask.nii.gz"));
  auto filter = GeodesicDistanceImageFilter<TensorImage>::New();
  filter->SetInput(tensors);
  filter->SetMaskImage(mask);
  filter->SetTensorFrame(ItkTensorFrame::indexAxes());  // DIPY: along the index axes
  filter->AddSeed({{55, 54, 15}});
  // Written and read by ITK, as a pipeline would.
  auto writer = itk::ImageFileWriter<ItkDistanceImage>::New();
  writer->SetInput(filter->GetOutput());
  writer->SetFileName(path("filter.nii.gz"));
  writer->Update();
  const ItkDistanceImage::Pointer written = readWithItk<ItkDistanceImage>(path("filter.nii.gz"));

  const std::vector<float> tool = toolDistances(sampleFile("dti_tensor_dipy5d.nii.gz"),
                                                {"--mask", sampleFile("dti_mask.nii.gz"), "--seed-voxel", "55,54,15"});
  ASSERT_EQ(tool.size(), 112u * 112u * 32u);
  ASSERT_EQ(written->GetBufferedRegion().GetNumberOfPixels(), tool.size());
  EXPECT_EQ(std::memcmp(written->GetBufferPointer(), tool.data(), tool.size() * sizeof(float)), 0);
  EXPECT_EQ(std::memcmp(filter->GetOutput()->GetBufferPointer(), tool.data(), tool.size() * sizeof(float)), 0);
  // The geometry is the input's (exactly in memory; through NIfTI's single
  // precision quaternion on disk).
  const ItkDistanceImage* out = filter->GetOutput();
  EXPECT_EQ(out->GetOrigin(), tensors->GetOrigin());
  EXPECT_EQ(out->GetSpacing(), tensors->GetSpacing());
  EXPECT_EQ(out->GetDirection(), tensors->GetDirection());
  EXPECT_EQ(out->GetBufferedRegion(), tensors->GetBufferedRegion());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(written->GetDirection()(r, c), tensors->GetDirection()(r, c), 1e-6);
  // Unreachable voxels hold -1, reached ones a distance.
  std::size_t unreachable = 0, reached = 0;
  for (float d : tool) (d == imaging::kItkUnreachableValue ? unreachable : reached) += 1;
  EXPECT_GT(unreachable, 0u);
  EXPECT_GT(reached, 100000u);
}

TEST_F(ItkBridge, TheNrrdMeasurementFrameIsReadByColumnsAndTheSpaceFlippedToLps) {
  // A NRRD in RAS space with a rotated measurement frame and rotated axes,
  // and tensors that differ in every component.
  HandGeometry g;
  g.size = {7, 6, 5};
  g.spacing = {1.5, 2.0, 2.5};
  g.originLps = {10, -20, 30};
  g.directionLps = rotation(1, 2, 3, 25);
  const imaging::Matrix3 frame = rotation(3, -1, 2, 40);
  std::vector<SymTensor3> components(g.grid().voxelCount());
  for (std::size_t v = 0; v < components.size(); ++v) {
    const float s = 1.f + 0.01f * static_cast<float>(v % 17);
    components[v] = {3.f * s, 0.4f, -0.3f, 2.f, 0.25f * s, 1.f};
  }
  writeTensorNrrdByHand(path("t.nrrd"), g, "right-anterior-superior", components, &frame);
  const TensorImage::Pointer image = readWithItk<TensorImage>(path("t.nrrd"));
  const imaging::TensorInput bridged = imaging::tensorInputFromItkImage(
      *image, ItkTensorFrame::nrrdMeasurementFrame(image->GetMetaDataDictionary()));
  const imaging::TensorReadResult read = imaging::readTensorVolume(path("t.nrrd"));
  ASSERT_EQ(bridged.read.volume.tensors.size(), read.volume.tensors.size());
  for (std::size_t v = 0; v < read.volume.tensors.size(); ++v)
    ASSERT_TRUE(sameBits(bridged.read.volume.tensors[v], read.volume.tensors[v])) << "voxel " << v;
  EXPECT_EQ(bridged.read.volume.geometry.origin, read.volume.geometry.origin);
  EXPECT_EQ(bridged.read.volume.geometry.direction, read.volume.geometry.direction);

  // Read as rows instead (the transposed frame), the tensors would differ:
  // the test can tell rows from columns.
  std::vector<std::vector<double>> rows(3, std::vector<double>(3));
  itk::ExposeMetaData(image->GetMetaDataDictionary(), "NRRD_measurement frame", rows);
  imaging::Matrix3 transposed{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) transposed[3 * r + c] = rows[r][c];
  const imaging::TensorInput wrong = imaging::tensorInputFromItkImage(
      *image, ItkTensorFrame::fromMatrix(imaging::multiply(imaging::rasToLps(), transposed), "rows"));
  EXPECT_GT(relativeDifference(wrong.read.volume.tensors[0], read.volume.tensors[0]), 0.05);
  // Without the flip from RAS, too.
  const imaging::TensorInput unflipped = imaging::tensorInputFromItkImage(
      *image, ItkTensorFrame::fromMatrix(transposed, "no flip"));
  EXPECT_GT(relativeDifference(unflipped.read.volume.tensors[0], read.volume.tensors[0]), 0.05);

  // And the filter's map is the tool's (metric tensors).
  auto filter = GeodesicDistanceImageFilter<TensorImage>::New();
  filter->SetInput(image);
  filter->SetTensorFrame(ItkTensorFrame::nrrdMeasurementFrame(image->GetMetaDataDictionary()));
  imaging::TensorInputOptions metric;
  imaging::setTensorKind(metric, "metric");
  filter->SetTensorOptions(metric);
  filter->AddSeed({{3, 2, 1}});
  filter->Update();
  const std::vector<float> tool = toolDistances(path("t.nrrd"), {"--tensor-kind", "metric", "--seed-voxel", "3,2,1"});
  ASSERT_EQ(tool.size(), components.size());
  EXPECT_EQ(std::memcmp(filter->GetOutput()->GetBufferPointer(), tool.data(), tool.size() * sizeof(float)), 0);
}

TEST_F(ItkBridge, AnImageWhoseRegionDoesNotStartAtZeroKeepsItsPlaceInSpace) {
  const TensorImage::Pointer whole = readWithItk<TensorImage>(sampleFile("dti_tensor_dipy5d.nii.gz"));
  TensorImage::RegionType part;
  part.SetIndex({{40, 30, 10}});
  part.SetSize({{30, 40, 12}});
  auto extract = itk::ExtractImageFilter<TensorImage, TensorImage>::New();
  extract->SetInput(whole);
  extract->SetExtractionRegion(part);
  extract->SetDirectionCollapseToIdentity();
  extract->Update();
  const TensorImage::Pointer image = extract->GetOutput();
  ASSERT_EQ(image->GetBufferedRegion().GetIndex(), part.GetIndex());  // the index is kept, the origin too

  const GridGeometry g = imaging::gridGeometryOf(*image);
  TensorImage::PointType corner;
  whole->TransformIndexToPhysicalPoint(part.GetIndex(), corner);
  for (int a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(g.origin[a], corner[a]);
  const Vec3d last = g.indexToPhysicalPoint(29, 39, 11);
  TensorImage::PointType lastItk;
  whole->TransformIndexToPhysicalPoint({{69, 69, 21}}, lastItk);
  EXPECT_NEAR(last.x, lastItk[0], 1e-9);
  EXPECT_NEAR(last.y, lastItk[1], 1e-9);
  EXPECT_NEAR(last.z, lastItk[2], 1e-9);

  const imaging::TensorInput partInput = imaging::tensorInputFromItkImage(*image, ItkTensorFrame::indexAxes());
  const imaging::TensorInput wholeInput = imaging::tensorInputFromItkImage(*whole, ItkTensorFrame::indexAxes());
  // Voxel (0, 0, 0) of the part is voxel (40, 30, 10) of the whole.
  EXPECT_TRUE(sameBits(partInput.read.volume.tensors[0], wholeInput.read.volume.tensors[40 + 112 * (30 + 112 * 10)]));

  // The filter takes seeds as indices of its input and gives a map on the
  // same region.
  auto filter = GeodesicDistanceImageFilter<TensorImage>::New();
  filter->SetInput(image);
  filter->SetTensorFrame(ItkTensorFrame::indexAxes());
  filter->AddSeed({{55, 54, 15}});
  filter->Update();
  const ItkDistanceImage* out = filter->GetOutput();
  EXPECT_EQ(out->GetBufferedRegion(), image->GetBufferedRegion());
  EXPECT_EQ(out->GetOrigin(), image->GetOrigin());
  EXPECT_EQ(out->GetPixel({{55, 54, 15}}), 0.f);
  // A seed outside the part is refused with stvd's message.
  filter->ClearSeeds();
  filter->AddSeed({{20, 54, 15}});
  try {
    filter->Update();
    ADD_FAILURE() << "a seed outside the image was accepted";
  } catch (const itk::ExceptionObject& e) {
    EXPECT_NE(std::string(e.GetDescription()).find("outside the image"), std::string::npos) << e.GetDescription();
  }
}

TEST_F(ItkBridge, TheFilterNeedsTheTensorFrame) {
  auto filter = GeodesicDistanceImageFilter<TensorImage>::New();
  filter->SetInput(readWithItk<TensorImage>(sampleFile("dti_tensor_dipy5d.nii.gz")));
  filter->AddSeed({{55, 54, 15}});
  try {
    filter->Update();
    ADD_FAILURE() << "no frame, yet no error";
  } catch (const itk::ExceptionObject& e) {
    EXPECT_NE(std::string(e.GetDescription()).find("tensor frame is not set"), std::string::npos)
        << e.GetDescription();
  }
}

TEST_F(ItkBridge, ProgressRunsFromZeroToOneAndAnAbortLeavesNoMap) {
  const TensorImage::Pointer tensors = readWithItk<TensorImage>(sampleFile("dti_tensor_dipy5d.nii.gz"));
  auto filter = GeodesicDistanceImageFilter<TensorImage>::New();
  filter->SetInput(tensors);
  filter->SetTensorFrame(ItkTensorFrame::indexAxes());
  filter->AddSeed({{55, 54, 15}});
  std::vector<float> seen;
  bool abort = false;
  auto onProgress = itk::CStyleCommand::New();
  struct Watch {
    GeodesicDistanceImageFilter<TensorImage>* filter;
    std::vector<float>* seen;
    bool* abort;
  } watch{filter.GetPointer(), &seen, &abort};
  onProgress->SetClientData(&watch);
  onProgress->SetCallback([](itk::Object*, const itk::EventObject&, void* data) {
    auto* w = static_cast<Watch*>(data);
    w->seen->push_back(w->filter->GetProgress());
    if (*w->abort && w->filter->GetProgress() > 0.f) w->filter->AbortGenerateDataOn();
  });
  filter->AddObserver(itk::ProgressEvent(), onProgress);
  filter->Update();
  ASSERT_GE(seen.size(), 3u);
  EXPECT_EQ(seen.front(), 0.f);
  EXPECT_EQ(seen.back(), 1.f);
  for (std::size_t n = 1; n < seen.size(); ++n) EXPECT_GE(seen[n], seen[n - 1]);
  // The path from a reached voxel back to the seed, as an ITK path in
  // continuous indices and in physical points.
  const imaging::ItkPath::Pointer indices = filter->TracePath({{70, 40, 15}});
  const imaging::ItkPath::Pointer points =
      filter->TracePath({{70, 40, 15}}, imaging::ItkPathCoordinates::Physical);
  ASSERT_GT(indices->GetVertexList()->Size(), 2u);
  const auto* first = indices->GetVertexList();
  EXPECT_NEAR(first->ElementAt(first->Size() - 1)[0], 70.0, 1e-6);
  EXPECT_NEAR(first->ElementAt(0)[0], 55.0, 1.0);
  const std::vector<Vec3d> a = imaging::pointsFromItkPath(*indices, *tensors, imaging::ItkPathCoordinates::ContinuousIndex);
  const std::vector<Vec3d> b = imaging::pointsFromItkPath(*points, *tensors, imaging::ItkPathCoordinates::Physical);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t n = 0; n < a.size(); ++n) EXPECT_NEAR(a[n].x, b[n].x, 1e-9);

  // An abort from the observer: Update() throws ProcessAborted and the
  // output holds no map.
  seen.clear();
  abort = true;
  filter->Modified();
  EXPECT_THROW(filter->Update(), itk::ProcessAborted);
  EXPECT_EQ(filter->GetOutput()->GetBufferPointer(), nullptr);
  EXPECT_LT(seen.back(), 1.f);
}

// With Lanthier's method the setup (the Steiner cells) and the
// propagation share the filter's range after the metric: its progress
// still never goes back (each reports 0 to 100 % on its own).
TEST_F(ItkBridge, WithSteinerPointsTheProgressNeverGoesBack) {
  const TensorImage::Pointer tensors = readWithItk<TensorImage>(sampleFile("dti_tensor_dipy5d.nii.gz"));
  auto filter = GeodesicDistanceImageFilter<TensorImage>::New();
  filter->SetInput(tensors);
  filter->SetTensorFrame(ItkTensorFrame::indexAxes());
  filter->AddSeed({{55, 54, 15}});
  PropagationChoice choice;
  choice.lanthier = true;
  choice.steinerPoints = 4;
  filter->SetPropagationChoice(choice);
  filter->SetMaximumDistance(10.0);
  std::vector<float> seen;
  auto onProgress = itk::CStyleCommand::New();
  struct Watch {
    GeodesicDistanceImageFilter<TensorImage>* filter;
    std::vector<float>* seen;
  } watch{filter.GetPointer(), &seen};
  onProgress->SetClientData(&watch);
  onProgress->SetCallback([](itk::Object*, const itk::EventObject&, void* data) {
    auto* w = static_cast<Watch*>(data);
    w->seen->push_back(w->filter->GetProgress());
  });
  filter->AddObserver(itk::ProgressEvent(), onProgress);
  filter->Update();
  ASSERT_GE(seen.size(), 3u);
  EXPECT_EQ(seen.front(), 0.f);
  EXPECT_EQ(seen.back(), 1.f);
  for (std::size_t n = 1; n < seen.size(); ++n) EXPECT_GE(seen[n], seen[n - 1]) << "report " << n;
}

}  // namespace
}  // namespace stvd::testing
