#include "stvd/imaging/tensor_layout.hpp"

namespace stvd::imaging {

std::optional<TensorOrder> parseTensorOrder(const std::string& name) {
  if (name == "lower" || name == "nifti") return TensorOrder::Lower;
  if (name == "fsl" || name == "upper") return TensorOrder::Fsl;
  if (name == "mrtrix") return TensorOrder::Mrtrix;
  return std::nullopt;
}

std::string tensorOrderName(TensorOrder order) {
  switch (order) {
    case TensorOrder::Lower: return "lower";
    case TensorOrder::Fsl: return "fsl";
    case TensorOrder::Mrtrix: return "mrtrix";
  }
  return "?";
}

std::string tensorOrderComponents(TensorOrder order) {
  switch (order) {
    case TensorOrder::Lower: return "xx,xy,yy,xz,yz,zz";
    case TensorOrder::Fsl: return "xx,xy,xz,yy,yz,zz";
    case TensorOrder::Mrtrix: return "xx,yy,zz,xy,xz,yz";
  }
  return "?";
}

std::optional<TensorFrame> parseTensorFrame(const std::string& name) {
  if (name == "voxel") return TensorFrame::Voxel;
  if (name == "world") return TensorFrame::World;
  return std::nullopt;
}

std::string tensorFrameName(TensorFrame frame) {
  return frame == TensorFrame::Voxel ? "voxel" : "world";
}

std::string tensorFileLayoutName(TensorFileLayout layout) {
  switch (layout) {
    case TensorFileLayout::NiftiSymMatrix5D: return "NIfTI 5D SYMMATRIX";
    case TensorFileLayout::NiftiSixVolumes: return "NIfTI six-volume";
    case TensorFileLayout::NrrdSymMatrix: return "NRRD 3D-symmetric-matrix";
    case TensorFileLayout::NrrdMaskedSymMatrix: return "NRRD 3D-masked-symmetric-matrix";
    case TensorFileLayout::MrtrixSixVolumes: return "MRtrix six-volume";
  }
  return "?";
}

TensorFrame defaultTensorFrame(TensorFileLayout layout, TensorOrder order) {
  switch (layout) {
    case TensorFileLayout::NrrdSymMatrix:
    case TensorFileLayout::NrrdMaskedSymMatrix: return TensorFrame::World;
    case TensorFileLayout::NiftiSymMatrix5D:
    case TensorFileLayout::NiftiSixVolumes:
    case TensorFileLayout::MrtrixSixVolumes:
      return order == TensorOrder::Mrtrix ? TensorFrame::World : TensorFrame::Voxel;
  }
  return TensorFrame::Voxel;
}

SymTensor3 tensorFromComponents(const float c[6], TensorOrder order) {
  switch (order) {
    case TensorOrder::Lower: return {c[0], c[1], c[3], c[2], c[4], c[5]};
    case TensorOrder::Fsl: return {c[0], c[1], c[2], c[3], c[4], c[5]};
    case TensorOrder::Mrtrix: return {c[0], c[3], c[4], c[1], c[5], c[2]};
  }
  return {};
}

void componentsOfTensor(const SymTensor3& t, TensorOrder order, float c[6]) {
  switch (order) {
    case TensorOrder::Lower:
      c[0] = t.xx; c[1] = t.xy; c[2] = t.yy; c[3] = t.xz; c[4] = t.yz; c[5] = t.zz;
      return;
    case TensorOrder::Fsl:
      c[0] = t.xx; c[1] = t.xy; c[2] = t.xz; c[3] = t.yy; c[4] = t.yz; c[5] = t.zz;
      return;
    case TensorOrder::Mrtrix:
      c[0] = t.xx; c[1] = t.yy; c[2] = t.zz; c[3] = t.xy; c[4] = t.xz; c[5] = t.yz;
      return;
  }
}

}  // namespace stvd::imaging
