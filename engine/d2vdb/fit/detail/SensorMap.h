// Internal: the linear map from a spline's control points to the positions of its sensors, grouped
// by knot span (curves) or knot cell (surfaces) for deterministic parallel assembly.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace d2vdb::detail {

/// Sensor k lies at x_k = sum_j weight(k, j) P[index(k, j)], j = 0..order()-1, with P the stored
/// control points of a curve or surface. Because knots stay fixed during a fit, x_k is linear in
/// the control points, which is what makes each fitting iteration one linear solve
/// (QuadraticModel).
///
/// Sensors are grouped (spanOrder(), spanBegin()) so that all sensors of a group share the same
/// control points (one knot span of a curve, one knot cell of a surface); assembly runs in parallel
/// over groups and still sums every contribution in a fixed order. Immutable after construction;
/// built by SensorBasis (curves) and SurfaceSensorBasis (surfaces).
class SensorMap {
 public:
  virtual ~SensorMap() = default;

  /// Number of sensors.
  int sensorCount() const { return sensorCount_; }
  /// Control points per sensor: p + 1 for a curve, (p + 1)(q + 1) for a surface.
  int order() const { return order_; }
  /// Number of stored control points of the spline.
  int controlPointCount() const { return controlPointCount_; }
  /// Index of the control point multiplying the j-th nonzero basis function of sensor k.
  int index(int k, int j) const { return indices_[static_cast<std::size_t>(k * order_ + j)]; }
  /// Value of the j-th nonzero basis function at sensor k.
  double weight(int k, int j) const { return weights_[static_cast<std::size_t>(k * order_ + j)]; }

  /// Tensor-product maps (surfaces; 0 for others): the basis functions per sensor in u, so that
  /// basis function j = a * (order() / orderU()) + b of sensor k is the product
  /// uWeight(k, a) * vWeight(k, b) of its u and v basis values (weight() holds the rounded
  /// product). Sensors with equal uKey() (vKey()) have the same u (v) parameter and so the same u
  /// (v) basis values: the fitting model sums a knot cell whose sensors form a grid direction by
  /// direction.
  int orderU() const { return orderU_; }
  double uWeight(int k, int a) const {
    return uWeights_[static_cast<std::size_t>(k * orderU_ + a)];
  }
  double vWeight(int k, int b) const {
    return vWeights_[static_cast<std::size_t>(k * (order_ / orderU_) + b)];
  }
  int uKey(int k) const { return uKeys_[static_cast<std::size_t>(k)]; }
  int vKey(int k) const { return vKeys_[static_cast<std::size_t>(k)]; }

  /// Sensor indices sorted by group (ties by index): sensors of group g are
  /// spanOrder()[spanBegin()[g] .. spanBegin()[g + 1]).
  const std::vector<int>& spanOrder() const { return spanOrder_; }
  /// Group boundaries into spanOrder(), one group per occupied knot span or cell, plus the end.
  const std::vector<int>& spanBegin() const { return spanBegin_; }

  /// Sensor positions for `controlPoints` (controlPointCount() of them), in parallel.
  std::vector<Eigen::Vector3d> positions(const std::vector<Eigen::Vector3d>& controlPoints) const;
  /// Position of sensor k for `controlPoints`.
  Eigen::Vector3d position(int k, const std::vector<Eigen::Vector3d>& controlPoints) const {
    Eigen::Vector3d x = Eigen::Vector3d::Zero();
    for (int j = 0; j < order_; ++j) {
      x += weight(k, j) * controlPoints[static_cast<std::size_t>(index(k, j))];
    }
    return x;
  }

 protected:
  /// Sizes the index and weight tables for `sensorCount` sensors of `order` entries each.
  SensorMap(int sensorCount, int order, int controlPointCount);
  /// Groups the sensors by `keys` (one non-negative integer per sensor, equal keys sharing their
  /// control points), in increasing key and, within a key, sensor order (a counting sort).
  void groupByKey(const std::vector<int>& keys);

  int sensorCount_ = 0;
  int order_ = 0;
  int controlPointCount_ = 0;
  std::vector<int> indices_;
  std::vector<double> weights_;
  // Tensor-product factors (orderU_ > 0): u and v basis values per sensor and parameter keys.
  int orderU_ = 0;
  std::vector<double> uWeights_;
  std::vector<double> vWeights_;
  std::vector<int> uKeys_;
  std::vector<int> vKeys_;

 private:
  std::vector<int> spanOrder_;
  std::vector<int> spanBegin_;
};

}  // namespace d2vdb::detail
