// No ITK header here: this file goes through symmetric_eigen.hpp only.
#include "stvd/imaging/tensor_metric.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "stvd/errors.hpp"
#include "stvd/imaging/symmetric_eigen.hpp"
#include "stvd/system/large_array.hpp"

namespace stvd::imaging {

std::optional<TensorKind> parseTensorKind(const std::string& name) {
  if (name == "diffusion") return TensorKind::Diffusion;
  if (name == "metric") return TensorKind::Metric;
  return std::nullopt;
}

std::string tensorKindName(TensorKind kind) { return kind == TensorKind::Diffusion ? "diffusion" : "metric"; }

std::optional<DiffusionMetric> parseDiffusionMetric(const std::string& name) {
  if (name == "inverse") return DiffusionMetric::NormalizedInverse;
  if (name == "adjugate") return DiffusionMetric::NormalizedAdjugate;
  return std::nullopt;
}

std::string diffusionMetricName(DiffusionMetric metric) {
  return metric == DiffusionMetric::NormalizedInverse ? "inverse" : "adjugate";
}

std::string metricFormula(TensorKind kind, DiffusionMetric metric) {
  if (kind == TensorKind::Metric) return "G as given";
  return metric == DiffusionMetric::NormalizedInverse ? "G = (D/MD)^-1" : "G = adj(D/MD)";
}

namespace {

bool isFinite(const SymTensor3& t) {
  return std::isfinite(t.xx) && std::isfinite(t.xy) && std::isfinite(t.xz) && std::isfinite(t.yy) &&
         std::isfinite(t.yz) && std::isfinite(t.zz);
}

bool isZero(const SymTensor3& t) {
  return t.xx == 0.f && t.xy == 0.f && t.xz == 0.f && t.yy == 0.f && t.yz == 0.f && t.zz == 0.f;
}

/// The metric's eigenvalues from the repaired tensor eigenvalues l (descending).
std::array<double, 3> metricEigenvalues(const std::array<double, 3>& l, const MetricOptions& options) {
  if (options.kind == TensorKind::Metric) return l;
  const double md = (l[0] + l[1] + l[2]) / 3.0;
  const std::array<double, 3> n{l[0] / md, l[1] / md, l[2] / md};  // eigenvalues of D/MD
  if (options.diffusionMetric == DiffusionMetric::NormalizedInverse) return {1.0 / n[0], 1.0 / n[1], 1.0 / n[2]};
  return {n[1] * n[2], n[0] * n[2], n[0] * n[1]};  // adjugate: product of the other two
}

}  // namespace

std::optional<double> anisotropyCap(const MetricOptions& options) {
  if (options.maxAnisotropy) return options.maxAnisotropy;
  if (options.kind == TensorKind::Diffusion) return kDefaultMaxAnisotropy;
  return std::nullopt;
}

MetricFromTensors buildMetric(const std::vector<SymTensor3>& tensors, const std::vector<std::uint8_t>& mask,
                              const MetricOptions& options, Interrupter* interrupter) {
  const std::optional<double> cap = anisotropyCap(options);
  if (cap && !(*cap >= 1.0)) throw std::invalid_argument("the anisotropy cap must be at least 1");
  if (!mask.empty() && mask.size() != tensors.size())
    throw std::invalid_argument("mask has " + std::to_string(mask.size()) + " voxels, the tensors " +
                                std::to_string(tensors.size()));
  MetricFromTensors out;
  const std::size_t n = tensors.size();
  // Read per neighbour in the propagation's inner loop: huge pages
  // (stvd/system/large_array.hpp).
  out.metric = makeLargeArray(n, SymTensor3{1.f, 0.f, 0.f, 1.f, 0.f, 1.f});
  out.inDomain.assign(n, 0);
  MetricVoxelCounts& c = out.counts;
  c.total = n;
  InterruptScope interrupt(interrupter, "metric", n);
  for (std::size_t v = 0; v < n; ++v) {
    interrupt.step(v);
    const SymTensor3& t = tensors[v];
    if (!mask.empty() && mask[v] == 0) { ++c.masked; continue; }
    if (!isFinite(t)) { ++c.nonFinite; continue; }
    if (isZero(t)) { ++c.zero; continue; }
    const SymmetricEigen e = eigenDecompose(t);
    if (!(e.values[2] > 0.0)) ++c.notPositiveDefinite;
    if (e.values[2] < 0.0 && fractionalAnisotropy(e.values) > 1.0) ++c.faAboveOne;
    if (!(e.values[0] > 0.0)) { ++c.noPositiveEigenvalue; continue; }
    if (options.faThreshold && fractionalAnisotropy(e.values) < *options.faThreshold) {
      ++c.belowFaThreshold;
      continue;
    }
    // Without a cap only non-positive eigenvalues are raised, to the
    // default cap's floor.
    const double floor = e.values[0] / cap.value_or(kDefaultMaxAnisotropy);
    std::array<double, 3> repaired = e.values;
    if (e.values[2] <= 0.0)
      ++c.repairedNonPositive;
    else if (cap && e.values[2] < floor)
      ++c.repairedAnisotropy;
    for (double& l : repaired)
      if (cap || l <= 0.0) l = std::max(l, floor);
    out.metric[v] = tensorFromEigen(metricEigenvalues(repaired, options), e.vectors);
    out.inDomain[v] = 1;
    ++c.domain;
  }
  interrupt.finish();
  return out;
}

void requireNonEmptyDomain(const std::string& inputName, const MetricVoxelCounts& counts, bool masked,
                           const MetricOptions& options) {
  if (counts.domain == 0)
    throw NothingToCompute(inputName + ": the domain is empty: no voxel has a usable tensor" +
                           (masked ? std::string(" inside the mask") : std::string()) +
                           (options.faThreshold ? " above the FA threshold" : ""));
}

std::vector<float> fractionalAnisotropyMap(const std::vector<SymTensor3>& tensors,
                                           const std::vector<std::uint8_t>& inDomain) {
  std::vector<float> fa(tensors.size(), 0.f);
  for (std::size_t v = 0; v < fa.size(); ++v)
    if (inDomain[v]) fa[v] = static_cast<float>(fractionalAnisotropy(eigenDecompose(tensors[v]).values));
  return fa;
}

}  // namespace stvd::imaging
