// Reading files reports to an Interrupter and can be stopped
// (docs/library.md "Progress and cancellation"): one operation per read,
// 0 % first, percents that never decrease, 100 % last; stopped, a read
// throws Cancelled and returns nothing. What a library call reads in one
// piece (ITK's read, the bytes of an MRtrix file) cannot be cut; what we
// loop over ourselves (decoding MRtrix values, components into tensors)
// reports as it goes, which the tests see with the report interval made
// zero (a report every 1024 steps). The work done is counted, never timed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "../core/interrupt_recorder.hpp"
#include "stvd/imaging/detail/read_progress.hpp"
#include "stvd/imaging/image_files.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

using namespace stvd::imaging;

bool sameTensors(const std::vector<SymTensor3>& a, const std::vector<SymTensor3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t v = 0; v < a.size(); ++v) {
    const SymTensor3& x = a[v];
    const SymTensor3& y = b[v];
    const bool nan = std::isnan(x.xx) && std::isnan(y.xx);
    if (!nan && (x.xx != y.xx || x.xy != y.xy || x.xz != y.xz || x.yy != y.yy || x.yz != y.yz || x.zz != y.zz))
      return false;
  }
  return true;
}

class ReadingInterruption : public ScratchFolderTest {
 protected:
  /// The sample brain's tensors as an MRtrix image (X Y Z 6).
  std::string mrtrixTensors() {
    const TensorReadResult read = readTensorVolume(sampleFile("dti_tensor_dipy5d.nii.gz"));
    const std::string file = path("tensors.mif");
    writeTensorVolume(file, read.volume, {TensorFileLayout::MrtrixSixVolumes, TensorOrder::Mrtrix, TensorFrame::Voxel});
    return file;
  }
};

// NIfTI, NRRD and MRtrix tensor files: "reading tensors" from 0 to 100 %,
// and the same tensors as a read without an interrupter.
TEST_F(ReadingInterruption, ReadingTensorsReportsZeroToHundredPercentInEveryFormat) {
  for (const std::string& file :
       {sampleFile("dti_tensor_dipy5d.nii.gz"), sampleFile("dti_tensor_teem.nrrd"), mrtrixTensors()}) {
    SCOPED_TRACE(file);
    InterruptRecorder recorder;
    const TensorReadResult read = readTensorVolume(file, {}, &recorder);
    ASSERT_EQ(recorder.operations().size(), 1u);
    EXPECT_EQ(recorder.operations()[0].name, "reading tensors");
    expectCompleteReports(recorder.operations()[0]);
    EXPECT_TRUE(sameTensors(read.volume.tensors, readTensorVolume(file).volume.tensors));
  }
}

// Masks, FA maps and labels: "reading image" and "reading labels".
TEST_F(ReadingInterruption, ReadingScalarAndLabelImagesReportsZeroToHundredPercent) {
  InterruptRecorder recorder;
  const ScalarImage fa = readScalarImage(sampleFile("dti_FA.nii.gz"), &recorder);
  const LabelImage mask = readLabelImage(sampleFile("dti_mask.nii.gz"), &recorder);
  writeScalarImage(path("fa.mif"), fa.geometry, fa.values);
  const ScalarImage faMrtrix = readScalarImage(path("fa.mif"), &recorder);
  EXPECT_EQ(faMrtrix.values, fa.values);
  EXPECT_EQ(mask.labels, readLabelImage(sampleFile("dti_mask.nii.gz")).labels);
  ASSERT_EQ(recorder.operations().size(), 3u);
  EXPECT_EQ(recorder.operations()[0].name, "reading image");
  EXPECT_EQ(recorder.operations()[1].name, "reading labels");
  EXPECT_EQ(recorder.operations()[2].name, "reading image");
  for (const InterruptRecorder::Operation& o : recorder.operations()) expectCompleteReports(o);
}

// Stopped at its start, a read throws Cancelled before it reads any data:
// a file truncated inside its data, which a read refuses once it reaches
// them, gives Cancelled, not the truncation's error.
TEST_F(ReadingInterruption, StoppedAtItsStartAReadThrowsCancelledBeforeReadingData) {
  const TensorReadResult read = readTensorVolume(sampleFile("dti_tensor_dipy5d.nii.gz"));
  const std::string nifti = path("truncated.nii"), mrtrix = path("truncated.mif");
  writeTensorVolume(nifti, read.volume, {TensorFileLayout::NiftiSymMatrix5D, TensorOrder::Lower, TensorFrame::Voxel});
  writeTensorVolume(mrtrix, read.volume, {TensorFileLayout::MrtrixSixVolumes, TensorOrder::Mrtrix, TensorFrame::Voxel});
  for (const std::string& file : {nifti, mrtrix}) {
    SCOPED_TRACE(file);
    std::filesystem::resize_file(file, std::filesystem::file_size(file) / 2);
    EXPECT_THROW(readTensorVolume(file), ImageIoError);
    InterruptRecorder recorder;
    recorder.stopAtStart();
    EXPECT_THROW(readTensorVolume(file, {}, &recorder), Cancelled);
    ASSERT_EQ(recorder.operations().size(), 1u);
    EXPECT_EQ(recorder.operations()[0].percents, (std::vector<int>{0}));
    EXPECT_TRUE(recorder.operations()[0].ended);
  }
  InterruptRecorder labels;
  labels.stopAtStart();
  EXPECT_THROW(readLabelImage(sampleFile("dti_mask.nii.gz"), &labels), Cancelled);
  InterruptRecorder scalars;
  scalars.stopAtStart();
  EXPECT_THROW(readScalarImage(sampleFile("dti_FA.nii.gz"), &scalars), Cancelled);
}

// The loops of our own report as they go: the conversion of components into
// tensors a step per voxel, the decoding of an MRtrix file's values a step
// per value after its bytes (read in one piece). Stopped at the first
// report after the start, nothing more is converted or decoded.
TEST_F(ReadingInterruption, OurOwnLoopsReportAsTheyGoAndStopAtTheNextReport) {
  const TensorReadResult read = readTensorVolume(sampleFile("dti_tensor_dipy5d.nii.gz"));
  const GridGeometry& g = read.volume.geometry;
  std::vector<float> components(6 * g.voxelCount(), 0.f);
  for (std::size_t v = 0; v < g.voxelCount(); ++v) components[6 * v] = components[6 * v + 3] = components[6 * v + 5] = 1.f;
  const TensorComponentLayout layout = componentsPerVoxel(g.size, TensorOrder::Fsl);
  const Matrix3 identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
  {
    InterruptRecorder all;
    std::vector<SymTensor3> tensors;
    {
      InterruptScope scope(&all, "tensors", g.voxelCount(), 0.0);
      tensors = imaging::detail::tensorsFromArray(components.data(), g.size, layout, identity, scope, 0);
      scope.finish();
    }
    EXPECT_EQ(tensors.size(), g.voxelCount());
    EXPECT_GE(all.operations()[0].percents.size(), g.voxelCount() / 1024);
    expectCompleteReports(all.operations()[0]);
  }
  {
    InterruptRecorder stopping;
    stopping.stopAtFirstReportAfterStart();
    InterruptScope scope(&stopping, "tensors", g.voxelCount(), 0.0);
    EXPECT_THROW(imaging::detail::tensorsFromArray(components.data(), g.size, layout, identity, scope, 0), Cancelled);
    // Stopped after 1024 of the voxels.
    EXPECT_EQ(stopping.operations()[0].percents, (std::vector<int>{0, static_cast<int>(100 * 1024 / g.voxelCount())}));
  }
  const std::string file = mrtrixTensors();
  {
    InterruptRecorder all;
    MrtrixImage image;
    {
      InterruptScope scope(&all, "reading image", 0, 0.0);
      image = imaging::detail::readMrtrixImage(file, scope);
      scope.finish();
    }
    const std::vector<int>& percents = all.operations()[0].percents;
    ASSERT_GE(percents.size(), 2u);
    EXPECT_EQ(percents[1], 50);  // the bytes are in, in one piece
    EXPECT_GE(percents.size(), image.values.size() / 1024);           // then a report every 1024 values
    expectCompleteReports(all.operations()[0]);
  }
  {
    InterruptRecorder stopping;
    stopping.stopAtFirstReportAfterStart();
    InterruptScope scope(&stopping, "reading image", 0, 0.0);
    EXPECT_THROW(imaging::detail::readMrtrixImage(file, scope), Cancelled);
    EXPECT_EQ(stopping.operations()[0].percents, (std::vector<int>{0, 50}));  // nothing decoded
  }
}

}  // namespace
}  // namespace stvd::testing
