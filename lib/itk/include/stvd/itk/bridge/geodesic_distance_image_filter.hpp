// stvd as an ITK filter: a tensor image in, the anisotropic geodesic
// distance map from seed voxels out, with ITK's progress events and
// AbortGenerateData, as ITK's FastMarchingImageFilter and
// MinimalPathExtraction's filters have them. Header-only; includes ITK.
#pragma once

#include <itkImageToImageFilter.h>
#include <itkMacro.h>
#include <itkProcessObject.h>

#include <array>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "stvd/errors.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/imaging/seed_voxels.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/itk/bridge/distance_image.hpp"
#include "stvd/itk/bridge/path.hpp"
#include "stvd/itk/bridge/tensor_image.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd::imaging {

/// Anisotropic geodesic distance from seed voxels over a tensor image.
///
/// Input: an itk::Image<itk::DiffusionTensor3D<T>, 3> or
/// itk::Image<itk::SymmetricSecondRankTensor<T, 3>, 3>; the whole image is
/// requested and used. Output: an ItkDistanceImage (float32 millimetres)
/// with the input's geometry (origin, spacing, direction, regions), where
/// voxels no distance reached hold GetUnreachableValue() (-1 by default).
///
/// Preconditions (each an exception from Update(), not a silent wrong
/// answer): the tensor frame is set (SetTensorFrame; there is no default,
/// see tensor_image.hpp), at least one seed is given and every seed lies in
/// the image and in the domain (itk::ExceptionObject carrying stvd's
/// message, which names the seed and why). The metric is made from the
/// tensors as `stvd distance` makes it (SetTensorOptions: diffusion or
/// metric tensors, inverse or adjugate, FA threshold, anisotropy cap; the
/// tool's defaults), the domain is the voxels with a usable tensor inside
/// the optional mask (SetMaskImage), the propagation is the tool's
/// (SetPropagationChoice; default STVD, k = 6, segment measure, stencil 26),
/// so that the output equals `stvd distance` run on the file the input was
/// read from, bit for bit.
///
/// Progress and abort: ProgressEvent is invoked at 0, then at least every
/// kDefaultInterruptInterval (0.05 s) while the metric is built (up to 10 %)
/// and while the front runs (the share of domain voxels finalised, up to
/// 100 %), and at 100 % at the end. Setting AbortGenerateData (from a
/// progress observer or another thread) stops the run at its next report,
/// within about 0.05 s, and Update() throws itk::ProcessAborted: no
/// partial distance map is produced (the output keeps no buffer).
///
/// After Update(), TracePath() gives the geodesic path from a voxel back to
/// the seeds (as `stvd path` traces it).
template <class TTensorImage>
class GeodesicDistanceImageFilter : public itk::ImageToImageFilter<TTensorImage, ItkDistanceImage> {
 public:
  ITK_DISALLOW_COPY_AND_MOVE(GeodesicDistanceImageFilter);
  using Self = GeodesicDistanceImageFilter;
  using Superclass = itk::ImageToImageFilter<TTensorImage, ItkDistanceImage>;
  using Pointer = itk::SmartPointer<Self>;
  using ConstPointer = itk::SmartPointer<const Self>;
  using IndexType = typename TTensorImage::IndexType;
  using MaskImageType = itk::Image<unsigned char, 3>;
  itkNewMacro(Self);
  itkTypeMacro(GeodesicDistanceImageFilter, ImageToImageFilter);

  /// The frame of the input's tensor components. Required.
  void SetTensorFrame(const ItkTensorFrame& frame) {
    frame_ = frame;
    this->Modified();
  }
  /// Adds a seed voxel, an index of the input image.
  void AddSeed(const IndexType& index) {
    seeds_.push_back(index);
    this->Modified();
  }
  void ClearSeeds() {
    seeds_.clear();
    this->Modified();
  }
  /// Voxels where the mask is 0 are outside the domain. Same grid as the
  /// input (buffered region), or Update() throws.
  void SetMaskImage(const MaskImageType* mask) {
    mask_ = mask;
    this->Modified();
  }
  /// How the metric is made from the tensors (the order, frame and mask
  /// path fields do not apply here and are ignored).
  void SetTensorOptions(const TensorInputOptions& options) {
    tensorOptions_ = options;
    this->Modified();
  }
  /// The propagation (method, k, chain measure, stencil, connectivity,
  /// Steiner points), checked as the tool checks it.
  void SetPropagationChoice(const PropagationChoice& choice) {
    choice_ = choice;
    this->Modified();
  }
  /// Stop once the front is farther than this (millimetres).
  itkSetMacro(MaximumDistance, double);
  itkGetConstMacro(MaximumDistance, double);
  /// The value of unreached voxels in the output (kItkUnreachableValue).
  itkSetMacro(UnreachableValue, float);
  itkGetConstMacro(UnreachableValue, float);

  /// The last run's result: distances per voxel of the input's buffered
  /// region (linear order), predecessors, counters.
  const PropagationResult& GetPropagationResult() const { return result_; }

  /// The geodesic path from `target` (an index of the input) back to the
  /// seeds, traced and refined on the distance field as `stvd path` does
  /// (path_tracing.hpp), as an ITK path in `coordinates`. Empty when the
  /// target was not reached. Throws itk::ExceptionObject before a
  /// successful Update(), for a target outside the image, and after a
  /// Steiner-point run (which keeps no predecessors).
  ItkPath::Pointer TracePath(const IndexType& target,
                             ItkPathCoordinates coordinates = ItkPathCoordinates::ContinuousIndex,
                             const PathTracingOptions& options = {}) const {
    if (!domain_) itkExceptionMacro("TracePath needs a successful Update() first");
    try {
      const TracedPath traced =
          traceGeodesicPath(*domain_, metric_, result_, vertexOf(target, *this->GetInput()), options);
      return itkPathFromPoints(traced.points, *this->GetInput(), coordinates);
    } catch (const std::exception& e) {
      itkExceptionMacro(<< e.what());
    }
  }

 protected:
  GeodesicDistanceImageFilter() = default;
  ~GeodesicDistanceImageFilter() override = default;

  void GenerateInputRequestedRegion() override {
    Superclass::GenerateInputRequestedRegion();
    if (auto* input = const_cast<TTensorImage*>(this->GetInput())) input->SetRequestedRegionToLargestPossibleRegion();
  }
  void EnlargeOutputRequestedRegion(itk::DataObject* output) override {
    Superclass::EnlargeOutputRequestedRegion(output);
    output->SetRequestedRegionToLargestPossibleRegion();
  }

  void GenerateData() override {
    domain_.reset();
    result_ = PropagationResult{};
    ItkDistanceImage* output = this->GetOutput();
    output->ReleaseData();  // no partial map survives a failure or an abort
    const TTensorImage& input = *this->GetInput();
    const std::string name = "the filter's tensor image";
    if (!frame_)
      itkExceptionMacro("the tensor frame is not set: call SetTensorFrame (ITK does not record the frame of tensor "
                        "components, and a wrong guess gives wrong distances)");
    if (seeds_.empty()) itkExceptionMacro("no seed: call AddSeed");
    PropagationResult result;
    try {
      checkPropagationChoice(choice_, /*lanthierAllowed=*/true);
      checkTensorInputOptions(tensorOptions_);
      TensorInput tensors = tensorInputFromItkImage(input, *frame_, name);
      if (mask_) addItkMask(tensors, *mask_, "the filter's mask image", name);
      PipelineInterrupter metricPhase(*this, 0.f, kMetricShare);
      MetricFromTensors built = buildCheckedMetric(name, tensors, tensorOptions_, nullptr, &metricPhase);
      requireNonEmptyDomain(name, built.counts, !tensors.mask.empty(), tensorOptions_.metric);
      std::vector<std::array<int, 3>> voxels;
      const auto first = input.GetBufferedRegion().GetIndex();
      for (const IndexType& s : seeds_)
        voxels.push_back({static_cast<int>(s[0] - first[0]), static_cast<int>(s[1] - first[1]),
                          static_cast<int>(s[2] - first[2])});
      const std::vector<SeedVoxel> seeds =
          seedVoxelsAt(name, voxels, {}, true, tensors, tensorOptions_.metric, built.inDomain);
      const GridGeometry& g = tensors.read.volume.geometry;
      domain_ = std::make_unique<VoxelGridDomain>(g, Stencil::byName(choice_.stencil), built.inDomain,
                                                  choice_.connectivity);
      metric_ = RiemannianMetric(std::move(built.metric), &built.inDomain);
      const std::vector<VertexId> sources = sourceVertices(*domain_, seeds);

      PipelineInterrupter propagationPhase(*this, kMetricShare, 1.f);
      if (choice_.lanthier) {
        LanthierOptions steiner;
        steiner.steinerPoints = choice_.steinerPoints > 0 ? choice_.steinerPoints : LanthierOptions{}.steinerPoints;
        steiner.maxDistance = m_MaximumDistance;
        steiner.interrupter = &propagationPhase;
        result = lanthierPropagate(*domain_, metric_, sources, steiner);
      } else {
        PropagationOptions options = propagationOptions(choice_);
        options.maxDistance = m_MaximumDistance;
        options.interrupter = &propagationPhase;
        result = propagate(*domain_, metric_, sources, options);
      }
    } catch (const itk::ProcessAborted&) {  // from a progress observer
      domain_.reset();
      throw;
    } catch (const Cancelled&) {  // while the metric was built
      domain_.reset();
      result.termination = Termination::Cancelled;
    } catch (const std::exception& e) {
      domain_.reset();
      itkExceptionMacro(<< e.what());
    }
    if (result.termination == Termination::Cancelled || this->GetAbortGenerateData()) {
      domain_.reset();
      itk::ProcessAborted aborted(__FILE__, __LINE__);
      aborted.SetDescription("the geodesic distance was aborted (AbortGenerateData): no distance map");
      throw aborted;
    }
    output->SetBufferedRegion(output->GetRequestedRegion());
    output->Allocate();
    fillDistanceImage(result.distance, *output, m_UnreachableValue);
    result_ = std::move(result);
    this->UpdateProgress(1.f);
  }

 private:
  /// The share of the progress the metric takes (it is much faster than
  /// the propagation).
  static constexpr float kMetricShare = 0.1f;

  /// The share of the propagation's progress that Lanthier's setup (the
  /// operation "Steiner cells" before "Steiner-point propagation") takes.
  static constexpr float kSteinerSetupShare = 0.2f;

  /// stvd's interrupter as the filter's progress (from..to) and abort. Each
  /// operation reports 0..100 %; Lanthier's setup and propagation share the
  /// range, so that the filter's progress never goes back.
  class PipelineInterrupter : public Interrupter {
   public:
    PipelineInterrupter(Self& filter, float from, float to)
        : filter_(filter), from_(from), to_(to), low_(from), high_(to) {}
    void start(const char* name) override {
      const float middle = from_ + kSteinerSetupShare * (to_ - from_);
      if (std::strcmp(name, "Steiner cells") == 0) {
        low_ = from_, high_ = middle;
      } else if (std::strcmp(name, "Steiner-point propagation") == 0) {
        low_ = middle, high_ = to_;
      } else {
        low_ = from_, high_ = to_;
      }
    }
    bool wasInterrupted(int percent) override {
      if (percent >= 0) filter_.UpdateProgress(low_ + (high_ - low_) * static_cast<float>(percent) / 100.f);
      return filter_.GetAbortGenerateData();
    }

   private:
    Self& filter_;
    float from_, to_;
    float low_, high_;  // the range of the operation under way
  };

  VertexId vertexOf(const IndexType& index, const TTensorImage& input) const {
    const auto first = input.GetBufferedRegion().GetIndex();
    return domain_->vertexAt(static_cast<int>(index[0] - first[0]), static_cast<int>(index[1] - first[1]),
                             static_cast<int>(index[2] - first[2]));
  }

  std::optional<ItkTensorFrame> frame_;
  std::vector<IndexType> seeds_;
  typename MaskImageType::ConstPointer mask_;
  TensorInputOptions tensorOptions_;
  PropagationChoice choice_;
  double m_MaximumDistance = std::numeric_limits<double>::infinity();
  float m_UnreachableValue = kItkUnreachableValue;
  std::unique_ptr<VoxelGridDomain> domain_;
  RiemannianMetric metric_;
  PropagationResult result_;
};

}  // namespace stvd::imaging
