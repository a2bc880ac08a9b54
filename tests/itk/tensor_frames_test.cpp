// Changing the frame of a tensor's components.
#include <gtest/gtest.h>

#include <cmath>

#include "stvd/imaging/tensor_frames.hpp"
#include "test_support.hpp"

namespace stvd::imaging {
namespace {

using stvd::testing::relativeDifference;
using stvd::testing::rotation;

TEST(ChangeTensorFrame, AQuarterTurnAboutZSwapsXAndY) {
  // The old x axis points along new y, old y along new -x.
  const Matrix3 quarterTurn{0, -1, 0, 1, 0, 0, 0, 0, 1};
  const SymTensor3 t{3.f, 0.5f, 0.25f, 1.f, 0.125f, 2.f};
  const SymTensor3 r = changeTensorFrame(t, quarterTurn);
  EXPECT_FLOAT_EQ(r.xx, 1.f);
  EXPECT_FLOAT_EQ(r.yy, 3.f);
  EXPECT_FLOAT_EQ(r.zz, 2.f);
  EXPECT_FLOAT_EQ(r.xy, -0.5f);
  EXPECT_FLOAT_EQ(r.xz, -0.125f);
  EXPECT_FLOAT_EQ(r.yz, 0.25f);
}

TEST(ChangeTensorFrame, AlignsTheMainAxisWithTheRotatedAxis) {
  // A tensor elongated along x, expressed in a frame whose x axis is the
  // unit vector u, is elongated along u: its quadratic form is largest there.
  const Matrix3 m = rotation(1, 2, 3, 40);
  const SymTensor3 t{10.f, 0.f, 0.f, 1.f, 0.f, 1.f};
  const SymTensor3 r = changeTensorFrame(t, m);
  const Vec3f u{static_cast<float>(m[0]), static_cast<float>(m[3]), static_cast<float>(m[6])};
  EXPECT_NEAR(r.quadraticForm(u), 10.f, 1e-5);
}

TEST(ChangeTensorFrame, RasToLpsNegatesOnlyTheCouplingsOfZWithXAndY) {
  const SymTensor3 t{1.f, 2.f, 3.f, 4.f, 5.f, 6.f};
  const SymTensor3 r = changeTensorFrame(t, rasToLps());
  EXPECT_EQ(r.xx, 1.f);
  EXPECT_EQ(r.xy, 2.f);
  EXPECT_EQ(r.xz, -3.f);
  EXPECT_EQ(r.yy, 4.f);
  EXPECT_EQ(r.yz, -5.f);
  EXPECT_EQ(r.zz, 6.f);
}

TEST(ChangeTensorFrame, ARotationAndItsTransposeCancel) {
  const Matrix3 m = rotation(-2, 1, 0.5, 73);
  const SymTensor3 t{2.f, 0.3f, -0.2f, 1.f, 0.1f, 0.5f};
  EXPECT_LT(relativeDifference(changeTensorFrame(changeTensorFrame(t, m), stvd::testing::transpose(m)), t), 1e-6);
}

TEST(Obliquity, IsZeroForPermutedAndFlippedAxesAndTheRotationAngleOtherwise) {
  GridGeometry g;
  g.direction = {0, -1, 0, 1, 0, 0, 0, 0, -1};
  EXPECT_NEAR(obliquityDegrees(g), 0.0, 1e-9);
  g.direction = rotation(0, 0, 1, 12);
  EXPECT_NEAR(obliquityDegrees(g), 12.0, 1e-9);
}

}  // namespace
}  // namespace stvd::imaging
