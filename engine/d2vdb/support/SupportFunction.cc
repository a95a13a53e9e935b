#include "d2vdb/support/SupportFunction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/support/SphereQuadrature.h"
#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/detail/HarmonicKernels.h"
#include "d2vdb/support/detail/SupportEvaluator.h"

namespace d2vdb {
namespace detail {

SupportEvaluator::SupportEvaluator(int degreeIn, const Eigen::VectorXd& c) : degree(degreeIn) {
  const int count = harmonicCount(degree);
  table = Eigen::MatrixXd::Zero(count, kQuantityCount);
  table.col(kValue) = c;
  for (int j = 0; j < count; ++j) {
    table(j, kRadialDefect) = (1.0 - harmonicDegreeOf(j)) * c[j];
  }
  if (degree >= 1) {
    const int lower = harmonicCount(degree - 1);
    Eigen::VectorXd gradient[3];
    for (int axis = 0; axis < 3; ++axis) {
      gradient[axis] = partialDerivativeMatrix(degree, axis) * c;
      table.col(kGradX + axis).head(lower) = gradient[axis];
    }
    if (degree >= 2) {
      const int lowest = harmonicCount(degree - 2);
      const Eigen::SparseMatrix<double> dx = partialDerivativeMatrix(degree - 1, 0);
      const Eigen::SparseMatrix<double> dy = partialDerivativeMatrix(degree - 1, 1);
      table.col(kHessXX).head(lowest) = dx * gradient[0];
      table.col(kHessXY).head(lowest) = dx * gradient[1];
      table.col(kHessXZ).head(lowest) = dx * gradient[2];
      table.col(kHessYY).head(lowest) = dy * gradient[1];
      table.col(kHessYZ).head(lowest) = dy * gradient[2];
    }
  }
}

void SupportEvaluator::evaluateBlock(int count, const Eigen::Vector3d* normals,
                                     Eigen::MatrixXd& basis, Eigen::MatrixXd& result,
                                     bool pointsOnly) const {
  double x[kSupportBlock];
  double y[kSupportBlock];
  double z[kSupportBlock];
  for (int i = 0; i < kSupportBlock; ++i) {
    const bool real = i < count;
    x[i] = real ? normals[i].x() : 0.0;
    y[i] = real ? normals[i].y() : 0.0;
    z[i] = real ? normals[i].z() : 1.0;
  }
  basis.resize(kSupportBlock, harmonicCount(degree));
  result.resize(kSupportBlock, kQuantityCount);
  evaluateHarmonicBlock(degree, kSupportBlock, x, y, z, basis.data(), kSupportBlock);
  if (pointsOnly) {
    result.leftCols(kGradZ + 1).noalias() = basis * table.leftCols(kGradZ + 1);
  } else {
    result.noalias() = basis * table;
  }
}

void tangentFrame(const Eigen::Vector3d& n, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  e1 = Eigen::Vector3d(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  e2 = Eigen::Vector3d(b, sign + n.y() * n.y() * a, -n.y());
}

SupportPoint assembleSupportPoint(const Eigen::Vector3d& n, const Eigen::MatrixXd& r,
                                  Eigen::Index row) {
  SupportPoint sp;
  sp.normal = n;
  sp.value = r(row, kValue);
  const double defect = r(row, kRadialDefect);
  const Eigen::Vector3d gradient(r(row, kGradX), r(row, kGradY), r(row, kGradZ));
  sp.surfaceGradient = gradient - n.dot(gradient) * n;
  sp.point = sp.value * n + sp.surfaceGradient;
  Eigen::Matrix3d hessian;
  const double xx = r(row, kHessXX);
  const double xy = r(row, kHessXY);
  const double xz = r(row, kHessXZ);
  const double yy = r(row, kHessYY);
  const double yz = r(row, kHessYZ);
  hessian << xx, xy, xz, xy, yy, yz, xz, yz, -xx - yy;
  Eigen::Vector3d e1;
  Eigen::Vector3d e2;
  tangentFrame(n, e1, e2);
  const Eigen::Vector3d he1 = hessian * e1;
  const Eigen::Vector3d he2 = hessian * e2;
  const double p = e1.dot(he1) + defect;
  const double q = 0.5 * (e1.dot(he2) + e2.dot(he1));
  const double s = e2.dot(he2) + defect;
  // Eigenvalues of [[p, q], [q, s]]; the one of smaller magnitude from det / (larger), which
  // avoids cancellation when the radii differ greatly.
  const double mean = 0.5 * (p + s);
  const double radius = std::hypot(0.5 * (p - s), q);
  const double det = p * s - q * q;
  double small = 0.0;
  double large = 0.0;
  if (mean >= 0.0) {
    large = mean + radius;
    small = large != 0.0 ? det / large : 0.0;
  } else {
    small = mean - radius;
    large = small != 0.0 ? det / small : 0.0;
  }
  sp.radius1 = std::min(small, large);
  sp.radius2 = std::max(small, large);
  // Eigenvector of the larger eigenvalue at angle theta from e1.
  const double theta = 0.5 * std::atan2(2.0 * q, p - s);
  const double c = std::cos(theta);
  const double sn = std::sin(theta);
  sp.direction2 = c * e1 + sn * e2;
  sp.direction1 = sp.direction2.cross(n);  // (direction1, direction2, n) right-handed
  return sp;
}

}  // namespace detail

namespace {

constexpr double kPi = 3.14159265358979323846;

// The unit vector of `normal`; the message is only built on failure (this runs per normal).
Eigen::Vector3d normalised(const Eigen::Vector3d& normal) {
  const double length = normal.norm();
  if (std::isfinite(length) && length > 1e-100) return normal / length;
  return unitNormalOrThrow(normal, "the normal (" + std::to_string(normal.x()) + ", " +
                                       std::to_string(normal.y()) + ", " +
                                       std::to_string(normal.z()) + ")");
}

std::vector<Eigen::Vector3d> normalisedAll(const std::vector<Eigen::Vector3d>& normals) {
  std::vector<Eigen::Vector3d> unit(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double length = normals[i].norm();
    unit[i] = std::isfinite(length) && length > 1e-100
                  ? Eigen::Vector3d(normals[i] / length)
                  : unitNormalOrThrow(normals[i], "normal " + std::to_string(i));
  }
  return unit;
}

// Runs `body(blockBegin, count, basis, result)` over fixed blocks of kSupportBlock normals in
// parallel; each task owns its scratch matrices.
template <typename Body>
void forEachBlock(std::size_t total, const Body& body) {
  const std::size_t blocks = (total + detail::kSupportBlock - 1) / detail::kSupportBlock;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 4),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      Eigen::MatrixXd basis;
                      Eigen::MatrixXd result;
                      for (std::size_t block = range.begin(); block != range.end(); ++block) {
                        const std::size_t begin = block * detail::kSupportBlock;
                        const int count = static_cast<int>(
                            std::min<std::size_t>(detail::kSupportBlock, total - begin));
                        body(begin, count, basis, result);
                      }
                    });
}

double degreeOneScale() {
  return std::sqrt(3.0 / (4.0 * kPi));
}

}  // namespace

SupportFunction::SupportFunction() : SupportFunction(0, Eigen::VectorXd::Zero(1)) {}

SupportFunction::SupportFunction(int degree, Eigen::VectorXd coefficients)
    : degree_(degree), coefficients_(std::move(coefficients)) {
  if (degree < 0 || degree > kMaxSupportDegree) {
    throw InputError("support function degree " + std::to_string(degree) +
                     " is not supported (expected 0 to " + std::to_string(kMaxSupportDegree) + ")");
  }
  if (coefficients_.size() != harmonicCount(degree)) {
    throw InputError("a support function of degree " + std::to_string(degree) + " needs " +
                     std::to_string(harmonicCount(degree)) + " coefficients, got " +
                     std::to_string(coefficients_.size()));
  }
  for (Eigen::Index j = 0; j < coefficients_.size(); ++j) {
    if (!std::isfinite(coefficients_[j])) {
      throw InputError("support function coefficient " + std::to_string(j) + " is not finite");
    }
  }
  evaluator_ = std::make_shared<const detail::SupportEvaluator>(degree_, coefficients_);
}

SupportFunction SupportFunction::sphere(const Eigen::Vector3d& centre, double radius, int degree) {
  if (degree < 1 || degree > kMaxSupportDegree) {
    throw InputError("a sphere's support function needs a degree from 1 to " +
                     std::to_string(kMaxSupportDegree) + ", got " + std::to_string(degree));
  }
  if (!std::isfinite(radius)) throw InputError("the sphere's radius is not finite");
  SupportFunction zero(degree, Eigen::VectorXd::Zero(harmonicCount(degree)));
  return zero.offset(radius).translated(centre);
}

double SupportFunction::value(const Eigen::Vector3d& normal) const {
  const Eigen::VectorXd basis = evaluateHarmonics(degree_, normalised(normal));
  return basis.dot(coefficients_);
}

Eigen::Vector3d SupportFunction::point(const Eigen::Vector3d& normal, double offset) const {
  const SupportPoint sp = evaluate(normal);
  return sp.point + offset * sp.normal;
}

SupportPoint SupportFunction::evaluate(const Eigen::Vector3d& normal) const {
  const Eigen::Vector3d n = normalised(normal);
  Eigen::MatrixXd basis(1, harmonicCount(degree_));
  detail::evaluateHarmonicBlock(degree_, 1, &n.x(), &n.y(), &n.z(), basis.data(), 1);
  const Eigen::MatrixXd result = basis * evaluator_->table;
  return detail::assembleSupportPoint(n, result, 0);
}

std::vector<SupportPoint> SupportFunction::evaluate(
    const std::vector<Eigen::Vector3d>& normals) const {
  const std::vector<Eigen::Vector3d> unit = normalisedAll(normals);
  std::vector<SupportPoint> out(unit.size());
  forEachBlock(unit.size(),
               [&](std::size_t begin, int count, Eigen::MatrixXd& basis, Eigen::MatrixXd& result) {
                 evaluator_->evaluateBlock(count, unit.data() + begin, basis, result, false);
                 for (int i = 0; i < count; ++i) {
                   out[begin + static_cast<std::size_t>(i)] = detail::assembleSupportPoint(
                       unit[begin + static_cast<std::size_t>(i)], result, i);
                 }
               });
  return out;
}

std::vector<Eigen::Vector3d> SupportFunction::points(const std::vector<Eigen::Vector3d>& normals,
                                                     double offset) const {
  if (!std::isfinite(offset)) throw InputError("the offset distance is not finite");
  const std::vector<Eigen::Vector3d> unit = normalisedAll(normals);
  std::vector<Eigen::Vector3d> out(unit.size());
  forEachBlock(unit.size(), [&](std::size_t begin, int count, Eigen::MatrixXd& basis,
                                Eigen::MatrixXd& result) {
    evaluator_->evaluateBlock(count, unit.data() + begin, basis, result, true);
    for (int i = 0; i < count; ++i) {
      const Eigen::Vector3d& n = unit[begin + static_cast<std::size_t>(i)];
      const Eigen::Vector3d gradient(result(i, detail::kGradX), result(i, detail::kGradY),
                                     result(i, detail::kGradZ));
      const double h = result(i, detail::kValue) + offset;
      out[begin + static_cast<std::size_t>(i)] = h * n + (gradient - n.dot(gradient) * n);
    }
  });
  return out;
}

SupportFunction SupportFunction::offset(double distance) const {
  if (!std::isfinite(distance)) throw InputError("the offset distance is not finite");
  Eigen::VectorXd c = coefficients_;
  c[0] += distance * std::sqrt(4.0 * kPi);
  return SupportFunction(degree_, std::move(c));
}

SupportFunction SupportFunction::translated(const Eigen::Vector3d& translation) const {
  if (!translation.allFinite()) throw InputError("the translation is not finite");
  const int degree = std::max(degree_, 1);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(harmonicCount(degree));
  c.head(coefficients_.size()) = coefficients_;
  const double scale = degreeOneScale();
  c[harmonicIndex(1, 1)] += translation.x() / scale;
  c[harmonicIndex(1, -1)] += translation.y() / scale;
  c[harmonicIndex(1, 0)] += translation.z() / scale;
  return SupportFunction(degree, std::move(c));
}

SupportFunction SupportFunction::rotated(const Eigen::Matrix3d& rotation) const {
  if (!rotation.allFinite() ||
      (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm() > 1e-9 ||
      rotation.determinant() < 0.0) {
    throw InputError("the rotation matrix is not orthogonal with determinant +1 (to 1e-9)");
  }
  // h'(n) = h(R^T n) lies in the same span; its coefficients are the exact integrals of h' Y_j,
  // polynomials of degree <= 2L, by a product rule exact to that degree.
  const SphereQuadrature rule = sphereQuadrature(2 * degree_);
  std::vector<Eigen::Vector3d> turned(rule.nodes.size());
  for (std::size_t q = 0; q < rule.nodes.size(); ++q)
    turned[q] = rotation.transpose() * rule.nodes[q];
  const int count = harmonicCount(degree_);
  Eigen::VectorXd c = Eigen::VectorXd::Zero(count);
  Eigen::MatrixXd basis(detail::kSupportBlock, count);
  Eigen::MatrixXd turnedBasis(detail::kSupportBlock, count);
  for (std::size_t begin = 0; begin < rule.nodes.size(); begin += detail::kSupportBlock) {
    const int block =
        static_cast<int>(std::min<std::size_t>(detail::kSupportBlock, rule.nodes.size() - begin));
    double x[detail::kSupportBlock], y[detail::kSupportBlock], z[detail::kSupportBlock];
    double tx[detail::kSupportBlock], ty[detail::kSupportBlock], tz[detail::kSupportBlock];
    for (int i = 0; i < block; ++i) {
      const auto k = begin + static_cast<std::size_t>(i);
      x[i] = rule.nodes[k].x();
      y[i] = rule.nodes[k].y();
      z[i] = rule.nodes[k].z();
      tx[i] = turned[k].x();
      ty[i] = turned[k].y();
      tz[i] = turned[k].z();
    }
    detail::evaluateHarmonicBlock(degree_, block, x, y, z, basis.data(), detail::kSupportBlock);
    detail::evaluateHarmonicBlock(degree_, block, tx, ty, tz, turnedBasis.data(),
                                  detail::kSupportBlock);
    const Eigen::VectorXd values = turnedBasis.topRows(block) * coefficients_;
    for (int i = 0; i < block; ++i) {
      c += (rule.weights[begin + static_cast<std::size_t>(i)] * values[i]) *
           basis.row(i).transpose();
    }
  }
  return SupportFunction(degree_, std::move(c));
}

SupportFunction SupportFunction::withDegree(int degree) const {
  if (degree < 0 || degree > kMaxSupportDegree) {
    throw InputError("support function degree " + std::to_string(degree) +
                     " is not supported (expected 0 to " + std::to_string(kMaxSupportDegree) + ")");
  }
  Eigen::VectorXd c = Eigen::VectorXd::Zero(harmonicCount(degree));
  const Eigen::Index common = std::min<Eigen::Index>(c.size(), coefficients_.size());
  c.head(common) = coefficients_.head(common);
  return SupportFunction(degree, std::move(c));
}

Eigen::Vector3d SupportFunction::linearPart() const {
  if (degree_ < 1) return Eigen::Vector3d::Zero();
  const double scale = degreeOneScale();
  return scale * Eigen::Vector3d(coefficients_[harmonicIndex(1, 1)],
                                 coefficients_[harmonicIndex(1, -1)],
                                 coefficients_[harmonicIndex(1, 0)]);
}

double SupportFunction::meanValue() const {
  return coefficients_[0] / std::sqrt(4.0 * kPi);
}

}  // namespace d2vdb
