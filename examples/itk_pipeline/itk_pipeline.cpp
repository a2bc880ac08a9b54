// stvd inside an ITK pipeline: ITK reads a DTI tensor image and a mask, the
// filter computes the anisotropic geodesic distance map from a seed voxel
// with a progress observer, ITK writes the map, and the geodesic path to a
// target voxel comes out as an itk::PolyLineParametricPath. A second run is
// aborted from another thread and must stop within 100 ms.
//
//   itk_pipeline TENSORS.nii.gz MASK.nii.gz I J K TI TJ TK OUT.nii.gz [REFERENCE.nii.gz]
//
// The tensors are DIPY's (components along the image's index axes). With
// REFERENCE (the map `stvd distance TENSORS --mask MASK --seed-voxel I,J,K`
// wrote), the map written here must equal it bit for bit.
#include <itkCommand.h>
#include <itkImageFileReader.h>
#include <itkImageFileWriter.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "stvd/itk/bridge.hpp"

using TensorImage = itk::Image<itk::DiffusionTensor3D<float>, 3>;
using MaskImage = itk::Image<unsigned char, 3>;
using Filter = stvd::imaging::GeodesicDistanceImageFilter<TensorImage>;
using Clock = std::chrono::steady_clock;

template <class TImage>
typename TImage::Pointer readImage(const char* path) {
  auto reader = itk::ImageFileReader<TImage>::New();
  reader->SetFileName(path);
  reader->Update();
  return reader->GetOutput();
}

int main(int argc, char** argv) {
  if (argc != 10 && argc != 11) {
    std::fprintf(stderr, "usage: itk_pipeline TENSORS MASK I J K TI TJ TK OUT [REFERENCE]\n");
    return 2;
  }
  try {
    const TensorImage::Pointer tensors = readImage<TensorImage>(argv[1]);
    const MaskImage::Pointer mask = readImage<MaskImage>(argv[2]);
    const TensorImage::IndexType seed{{std::atol(argv[3]), std::atol(argv[4]), std::atol(argv[5])}};
    const TensorImage::IndexType target{{std::atol(argv[6]), std::atol(argv[7]), std::atol(argv[8])}};

    auto filter = Filter::New();
    filter->SetInput(tensors);
    filter->SetMaskImage(mask);
    filter->SetTensorFrame(stvd::imaging::ItkTensorFrame::indexAxes());  // DIPY's frame
    filter->AddSeed(seed);

    // Progress as a GUI would show it.
    std::vector<float> progress;
    auto onProgress = itk::CStyleCommand::New();
    onProgress->SetClientData(&progress);
    onProgress->SetCallback([](itk::Object* caller, const itk::EventObject&, void* data) {
      static_cast<std::vector<float>*>(data)->push_back(static_cast<Filter*>(caller)->GetProgress());
    });
    filter->AddObserver(itk::ProgressEvent(), onProgress);

    auto writer = itk::ImageFileWriter<stvd::imaging::ItkDistanceImage>::New();
    writer->SetInput(filter->GetOutput());
    writer->SetFileName(argv[9]);
    writer->Update();
    std::printf("progress: %zu events, from %.0f %% to %.0f %%\n", progress.size(), 100.0 * progress.front(),
                100.0 * progress.back());
    if (progress.size() < 3 || progress.front() != 0.f || progress.back() != 1.f) {
      std::fprintf(stderr, "itk_pipeline: progress did not run from 0 to 100 %%\n");
      return 1;
    }

    const stvd::imaging::ItkPath::Pointer path = filter->TracePath(target);
    const auto* vertices = path->GetVertexList();
    if (vertices->Size() < 2) {
      std::fprintf(stderr, "itk_pipeline: no path to the target\n");
      return 1;
    }
    std::printf("path: %u vertices (continuous indices) from (%.2f, %.2f, %.2f) to (%.2f, %.2f, %.2f), %.2f mm\n",
                static_cast<unsigned>(vertices->Size()), vertices->ElementAt(0)[0], vertices->ElementAt(0)[1],
                vertices->ElementAt(0)[2], vertices->ElementAt(vertices->Size() - 1)[0],
                vertices->ElementAt(vertices->Size() - 1)[1], vertices->ElementAt(vertices->Size() - 1)[2],
                filter->GetOutput()->GetPixel(target));

    if (argc == 11) {
      const auto reference = readImage<stvd::imaging::ItkDistanceImage>(argv[10]);
      const auto written = readImage<stvd::imaging::ItkDistanceImage>(argv[9]);
      const std::size_t n = written->GetBufferedRegion().GetNumberOfPixels();
      if (reference->GetBufferedRegion().GetNumberOfPixels() != n ||
          std::memcmp(reference->GetBufferPointer(), written->GetBufferPointer(), n * sizeof(float)) != 0) {
        std::fprintf(stderr, "itk_pipeline: the map differs from %s\n", argv[10]);
        return 1;
      }
      std::printf("the map equals %s bit for bit (%zu voxels)\n", argv[10], n);
    }

    // An abort from another thread (a GUI's cancel button): the run stops
    // within 100 ms and leaves no map.
    filter->Modified();
    std::atomic<bool> started{false};
    Clock::time_point abortedAt;
    auto onStart = itk::CStyleCommand::New();
    onStart->SetClientData(&started);
    onStart->SetCallback([](itk::Object*, const itk::EventObject&, void* data) {
      static_cast<std::atomic<bool>*>(data)->store(true);
    });
    filter->AddObserver(itk::StartEvent(), onStart);
    std::thread cancel([&] {
      while (!started) std::this_thread::yield();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      abortedAt = Clock::now();
      filter->AbortGenerateDataOn();
    });
    bool aborted = false;
    try {
      filter->Update();
    } catch (const itk::ProcessAborted&) {
      aborted = true;
    }
    const Clock::time_point stopped = Clock::now();
    cancel.join();
    if (!aborted) {
      std::printf("the run ended before the abort came\n");
      return 0;
    }
    const double ms = std::chrono::duration<double, std::milli>(stopped - abortedAt).count();
    std::printf("aborted: stopped %.1f ms after the abort, %s map\n", ms,
                filter->GetOutput()->GetBufferPointer() ? "with a" : "no");
    if (ms > 100.0 || filter->GetOutput()->GetBufferPointer()) return 1;
    return 0;
  } catch (const itk::ExceptionObject& e) {
    std::fprintf(stderr, "itk_pipeline: %s\n", e.GetDescription());
    return 1;
  }
}
