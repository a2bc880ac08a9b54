// Basic value types shared by every part of stvd: vertex handles, small
// vectors and the symmetric 3x3 tensor with its explicit component order.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "stvd/detail/compiler.hpp"

namespace stvd {

/// Index of a vertex in a domain (a voxel of a grid, a node of a mesh).
using VertexId = std::uint32_t;

/// "No vertex": the predecessor of a source and of every vertex not reached.
inline constexpr VertexId kNoVertex = std::numeric_limits<VertexId>::max();

/// Distance reported for a vertex that the propagation did not reach
/// (disconnected, masked off, beyond the maximum distance, or not finalised
/// before an early stop). Never 0.
inline constexpr double kUnreachable = std::numeric_limits<double>::infinity();

/// Single-precision 3-vector: edge vectors and tangent vectors in the hot
/// loops, where float is accurate enough (relative error ~1e-7 per edge).
struct Vec3f {
  float x = 0.f, y = 0.f, z = 0.f;
};

inline Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3f operator*(float s, Vec3f a) { return {s * a.x, s * a.y, s * a.z}; }
inline float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// Double-precision 3-vector: physical points (millimetres).
struct Vec3d {
  double x = 0.0, y = 0.0, z = 0.0;
};

inline Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d operator*(double s, Vec3d a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double norm(Vec3d a) { return std::sqrt(dot(a, a)); }
inline Vec3d cross(Vec3d a, Vec3d b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline Vec3f toFloat(Vec3d a) {
  return {static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z)};
}

/// Symmetric 3x3 tensor, stored as its upper triangle in the order
/// xx, xy, xz, yy, yz, zz (row-major upper triangle). Every reader and
/// writer converts to and from this order explicitly.
struct SymTensor3 {
  float xx = 0.f, xy = 0.f, xz = 0.f, yy = 0.f, yz = 0.f, zz = 0.f;

  /// The quadratic form v^T T v.
  float quadraticForm(Vec3f v) const {
    return xx * v.x * v.x + yy * v.y * v.y + zz * v.z * v.z +
           2.f * (xy * v.x * v.y + xz * v.x * v.z + yz * v.y * v.z);
  }
  /// T v.
  Vec3f apply(Vec3f v) const {
    return {xx * v.x + xy * v.y + xz * v.z, xy * v.x + yy * v.y + yz * v.z,
            xz * v.x + yz * v.y + zz * v.z};
  }
};

}  // namespace stvd
