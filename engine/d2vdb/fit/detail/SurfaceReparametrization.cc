// Chord-length re-parametrisation of a B-spline surface (detail/SurfaceReparametrization.h).
#include "d2vdb/fit/detail/SurfaceReparametrization.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/fit/detail/QuadraticModel.h"
#include "d2vdb/fit/detail/SurfaceSensorBasis.h"

namespace d2vdb::detail {
namespace {

/// Chord-length steps per control point along a line, and lines per control point across.
constexpr int kStepsPerControlPoint = 64;
constexpr int kLinesPerControlPoint = 4;
/// Least-squares samples per knot span in each direction.
constexpr int kSamplesPerSpan = 8;

/// The mean normalised chord length along one direction: entry i is the fraction of the length
/// reached at the parameter fraction i / (size - 1), averaged over lines of the other direction.
/// Empty when every line has zero length.
std::vector<double> meanChordFractions(const BSplineSurface& surface, bool alongV) {
  const ParameterInterval along = alongV ? surface.domainV() : surface.domainU();
  const ParameterInterval across = alongV ? surface.domainU() : surface.domainV();
  const int count = alongV ? surface.countV() : surface.countU();
  const int acrossCount = alongV ? surface.countU() : surface.countV();
  const int steps = kStepsPerControlPoint * count;
  const int lines = kLinesPerControlPoint * acrossCount;
  const auto at = [&](double a, double b) {
    return alongV ? surface.evaluate(b, a) : surface.evaluate(a, b);
  };
  std::vector<double> mean(static_cast<std::size_t>(steps) + 1, 0.0);
  std::vector<double> cumulative(mean.size(), 0.0);
  int used = 0;
  for (int line = 0; line < lines; ++line) {
    const double b = across.at((line + 0.5) / lines);
    Eigen::Vector3d previous = at(along.start, b);
    for (int i = 1; i <= steps; ++i) {
      const Eigen::Vector3d point = at(i == steps ? along.end : along.at(double(i) / steps), b);
      cumulative[static_cast<std::size_t>(i)] =
          cumulative[static_cast<std::size_t>(i) - 1] + (point - previous).norm();
      previous = point;
    }
    const double length = cumulative.back();
    if (!(length > 0.0)) continue;
    for (std::size_t i = 0; i < mean.size(); ++i) mean[i] += cumulative[i] / length;
    ++used;
  }
  if (used == 0) return {};
  for (double& value : mean) value /= used;
  return mean;
}

/// The parameter fraction at which `fractions` (non-decreasing, from meanChordFractions) reaches
/// `target`, by linear interpolation; the identity when `fractions` is empty.
double inverseFraction(const std::vector<double>& fractions, double target) {
  if (fractions.empty()) return target;
  const int steps = static_cast<int>(fractions.size()) - 1;
  const auto above = std::upper_bound(fractions.begin(), fractions.end(), target);
  const int i = std::clamp(static_cast<int>(above - fractions.begin()) - 1, 0, steps - 1);
  const double low = fractions[static_cast<std::size_t>(i)];
  const double high = fractions[static_cast<std::size_t>(i) + 1];
  const double t = high > low ? std::clamp((target - low) / (high - low), 0.0, 1.0) : 0.0;
  return (i + t) / steps;
}

}  // namespace

Reparametrization chordLengthReparametrized(const BSplineSurface& surface) {
  const std::vector<double> fractionsU = meanChordFractions(surface, false);
  const std::vector<double> fractionsV = meanChordFractions(surface, true);
  double shift = 0.0;
  for (const std::vector<double>* fractions : {&fractionsU, &fractionsV}) {
    const std::size_t steps = fractions->empty() ? 0 : fractions->size() - 1;
    for (std::size_t i = 0; i <= steps && steps > 0; ++i) {
      shift = std::max(shift, std::abs((*fractions)[i] - static_cast<double>(i) / steps));
    }
  }
  const ParameterInterval domainU = surface.domainU();
  const ParameterInterval domainV = surface.domainV();
  std::vector<Eigen::Vector2d> parameters =
      uniformSurfaceSensorParameters(surface, kSamplesPerSpan);
  std::vector<QuadraticForm> forms(parameters.size());
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const Eigen::Vector2d& uv = parameters[k];
    const double fractionU = (uv.x() - domainU.start) / domainU.length();
    const double fractionV = (uv.y() - domainV.start) / domainV.length();
    const Eigen::Vector3d point =
        surface.evaluate(domainU.at(inverseFraction(fractionsU, fractionU)),
                         domainV.at(inverseFraction(fractionsV, fractionV)));
    forms[k].A = Eigen::Matrix3d::Identity();
    forms[k].b = point;
    forms[k].c = point.squaredNorm();
  }
  const SurfaceSensorBasis basis(surface, std::move(parameters));
  QuadraticModel model(surface.countU() * surface.countV(), 3, {});
  std::vector<Eigen::Vector3d> controlPoints = surface.controlPoints();
  const std::vector<Eigen::Vector3d> step = model.solve(basis, forms, controlPoints, 0.0);
  for (std::size_t i = 0; i < controlPoints.size(); ++i) controlPoints[i] += step[i];
  Reparametrization result{surface, shift};
  result.surface.setControlPoints(std::move(controlPoints));
  return result;
}

}  // namespace d2vdb::detail
