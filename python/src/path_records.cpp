#include "path_records.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <utility>

#include "array_access.hpp"
#include "stvd/imaging/streamline_io.hpp"

namespace stvd::python {

py::dict pathRecord(const VoxelGridDomain& domain, const imaging::PathTarget& target, const TracedPath& path,
                    const PathSamples* fa) {
  py::array_t<double> points({static_cast<py::ssize_t>(path.points.size()), py::ssize_t{3}});
  auto w = points.mutable_unchecked<2>();
  for (std::size_t n = 0; n < path.points.size(); ++n) {
    const Vec3d ras = imaging::lpsToRas(path.points[n]);
    w(n, 0) = ras.x;
    w(n, 1) = ras.y;
    w(n, 2) = ras.z;
  }
  const VoxelIndex ti = domain.indexOf(target.vertex), si = domain.indexOf(path.discrete.front());
  py::dict fallbacks;
  for (int f = 0; f < kPathFallbackKinds; ++f)
    if (path.fallbacks[f]) fallbacks[pathFallbackName(static_cast<PathFallback>(f))] = path.fallbacks[f];
  py::dict d;
  d["points"] = points;
  d["target"] = target.name;
  d["target_voxel"] = py::make_tuple(ti.i, ti.j, ti.k);
  d["seed_voxel"] = py::make_tuple(si.i, si.j, si.k);
  d["geodesic_mm"] = path.geodesicLength;
  d["euclidean_mm"] = path.euclideanLength;
  d["straight_mm"] = norm(domain.physicalPoint(target.vertex) - domain.physicalPoint(path.discrete.front()));
  d["metric_length_mm"] = path.metricLength;
  d["mean_fa"] = fa ? fa->lengthWeightedMean : std::numeric_limits<double>::quiet_NaN();
  d["fa"] = fa ? py::object(py::array_t<float>(fa->values.size(), fa->values.data())) : py::object(py::none());
  d["gradient_steps"] = path.gradientSteps;
  d["discrete_points"] = path.discretePoints;
  d["fallbacks"] = fallbacks;
  d["refine_iterations"] = path.refinement.iterations;
  return d;
}

void writePathsOnGrid(const GridGeometry& g, files::OutputTransaction& outputs, const std::string& path,
                      const py::list& lines, const std::vector<double>& geodesic, const std::vector<double>& euclidean,
                      const std::optional<std::vector<double>>& meanFa, const py::object& fa) {
  // The streamline set of `stvd path` (stvd/imaging/streamline_io.hpp).
  imaging::StreamlineSet set;
  set.geometry = g;
  for (const py::handle& line : lines) {
    std::vector<Vec3d> lps;
    // The flip between RAS and LPS is its own inverse.
    for (const Vec3d& ras : pointRows(line, "paths")) lps.push_back(imaging::lpsToRas(ras));
    set.lines.push_back(std::move(lps));
  }
  set.lineValueNames = {"geodesic_mm", "euclidean_mm"};
  set.lineValues = {std::vector<float>(geodesic.begin(), geodesic.end()),
                    std::vector<float>(euclidean.begin(), euclidean.end())};
  if (meanFa) {
    set.lineValueNames.push_back("mean_fa");
    set.lineValues.emplace_back(meanFa->begin(), meanFa->end());
    set.pointValueNames = {"fa"};
    set.pointValues.resize(1);
    for (const py::handle& values : fa) set.pointValues[0].push_back(values.cast<std::vector<float>>());
  }
  py::gil_scoped_release release;
  imaging::writeStreamlines(outputs, path, set);
}

py::dict connectivityDict(const std::vector<LabelRegion>& regions, const RegionConnectivity& table,
                          std::size_t labelsLeftOut) {
  const py::ssize_t n = static_cast<py::ssize_t>(regions.size());
  py::array_t<long long> labelValues(n), voxelCounts(n);
  py::array_t<double> geodesic({n, n}), pathLength({n, n}), straight({n, n}), index({n, n});
  auto g = geodesic.mutable_unchecked<2>(), l = pathLength.mutable_unchecked<2>(), s = straight.mutable_unchecked<2>(),
       c = index.mutable_unchecked<2>();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (py::ssize_t a = 0; a < n; ++a) {
    labelValues.mutable_at(a) = regions[a].label;
    voxelCounts.mutable_at(a) = static_cast<long long>(regions[a].voxels.size());
    for (py::ssize_t b = 0; b < n; ++b) {
      const RegionPair& r = table(a, b);
      const bool measured = a != b && std::isfinite(r.geodesic);
      g(a, b) = measured ? r.geodesic : nan;
      l(a, b) = measured ? r.pathLength : nan;
      s(a, b) = measured ? r.straight : nan;
      c(a, b) = measured ? r.connectivity() : nan;
    }
  }
  py::dict d;
  d["labels"] = labelValues;
  d["voxels"] = voxelCounts;
  d["geodesic_mm"] = geodesic;
  d["path_mm"] = pathLength;
  d["straight_mm"] = straight;
  d["connectivity"] = index;
  d["labels_left_out"] = labelsLeftOut;
  d["threads"] = table.threads;
  return d;
}

}  // namespace stvd::python
