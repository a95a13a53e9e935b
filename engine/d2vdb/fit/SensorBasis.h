// The linear map from a B-spline curve's control points to the positions of its sensors.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/spline/BSplineCurve.h"

namespace d2vdb {

/// Sensors of a curve at fixed parameter values and the B-spline basis there: sensor k lies at
/// x_k = sum_j weight(k, j) P[index(k, j)], j = 0..p, with P the curve's stored control points
/// (closed curves wrap through BSplineCurve::controlPointIndex). Because knots stay fixed, x_k is
/// linear in the control points, which is what makes each fitting iteration one linear solve.
///
/// Sensors are also grouped by knot span (spanOrder(), spanBegin()) so that assembly can run in
/// parallel over spans and still sum every contribution in a fixed order. Immutable.
class SensorBasis {
 public:
  /// Evaluates the basis at `parameters` (each in the curve's domain; closed curves wrap), in
  /// parallel. Throws InputError for a parameter outside an open curve's domain or NaN.
  SensorBasis(const BSplineCurve& curve, std::vector<double> parameters);

  /// Number of sensors.
  int sensorCount() const { return static_cast<int>(parameters_.size()); }
  /// p + 1: control points per sensor.
  int order() const { return order_; }
  /// Number of stored control points of the curve.
  int controlPointCount() const { return controlPointCount_; }
  /// Parameter of sensor k.
  double parameter(int k) const { return parameters_[static_cast<std::size_t>(k)]; }
  /// All sensor parameters.
  const std::vector<double>& parameters() const { return parameters_; }
  /// Index of the control point multiplying the j-th nonzero basis function of sensor k.
  int index(int k, int j) const { return indices_[static_cast<std::size_t>(k * order_ + j)]; }
  /// Value of the j-th nonzero basis function at sensor k.
  double weight(int k, int j) const { return weights_[static_cast<std::size_t>(k * order_ + j)]; }

  /// Sensor indices sorted by knot span (ties by index): sensors of span group g are
  /// spanOrder()[spanBegin()[g] .. spanBegin()[g + 1]).
  const std::vector<int>& spanOrder() const { return spanOrder_; }
  /// Group boundaries into spanOrder(), one group per occupied knot span, plus the end.
  const std::vector<int>& spanBegin() const { return spanBegin_; }

  /// Sensor positions for `controlPoints` (same count as the curve's), in parallel.
  std::vector<Eigen::Vector3d> positions(const std::vector<Eigen::Vector3d>& controlPoints) const;
  /// Position of sensor k for `controlPoints` (same count as the curve's).
  Eigen::Vector3d position(int k, const std::vector<Eigen::Vector3d>& controlPoints) const {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int j = 0; j < order_; ++j) {
      x += weight(k, j) * controlPoints[static_cast<std::size_t>(index(k, j))];
    }
    return x;
  }

 private:
  std::vector<double> parameters_;
  int order_ = 0;
  int controlPointCount_ = 0;
  std::vector<int> indices_;
  std::vector<double> weights_;
  std::vector<int> spans_;
  std::vector<int> spanOrder_;
  std::vector<int> spanBegin_;
};

/// Parameters of `perSpan` >= 1 sensors in every non-empty knot span of the curve's domain, at
/// the midpoints of perSpan equal parts of the span, plus both domain ends for an open curve (so
/// that its ends are held too), ascending. InputError for perSpan < 1.
std::vector<double> uniformSensorParameters(const BSplineCurve& curve, int perSpan);

}  // namespace d2vdb
