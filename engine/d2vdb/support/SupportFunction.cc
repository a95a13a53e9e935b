// Evaluating a support function in spherical harmonics: values, surface points, gradients and
// principal radii, in blocks of normals.
#include "d2vdb/support/SupportFunction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/support/SphereQuadrature.h"
#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/detail/HarmonicKernels.h"
#include "d2vdb/support/detail/SupportEvaluator.h"

namespace d2vdb {
namespace detail {

SupportEvaluator::SupportEvaluator(int degreeIn, const Eigen::VectorXd& c) : degree(degreeIn) {
  const int count = harmonicCount(degree);
  // Column q: the coefficients of quantity q in the harmonic basis.
  Eigen::MatrixXd table = Eigen::MatrixXd::Zero(count, kQuantityCount);
  table.col(kValue) = c;
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
  const RecurrenceTables& recurrence = recurrenceTables();
  recordOffset.resize(static_cast<std::size_t>(degree) + 1);
  records.clear();
  const auto push = [&](double value) { records.insert(records.end(), kLanes, value); };
  for (int m = 0; m <= degree; ++m) {
    recordOffset[static_cast<std::size_t>(m)] = records.size();
    for (int l = m; l <= degree; ++l) {
      const auto ul = static_cast<std::size_t>(l);
      const auto um = static_cast<std::size_t>(m);
      push(l == m ? recurrence.sectoral[um] : recurrence.a[ul][um]);
      push(l >= m + 2 ? recurrence.b[ul][um] : 0.0);
      for (int q = 0; q < kQuantityCount; ++q) push(table(harmonicIndex(l, m), q));
      for (int q = 0; q < kQuantityCount; ++q) push(m > 0 ? table(harmonicIndex(l, -m), q) : 0.0);
    }
  }
}

namespace {

// Loads and stores of kLanes consecutive doubles (any alignment).
inline Lanes load(const double* p) {
  Lanes value;
  std::memcpy(&value, p, sizeof value);
  return value;
}
inline void store(double* p, Lanes value) {
  std::memcpy(p, &value, sizeof value);
}
inline Lanes splat(double value) {
  return Lanes{} + value;  // every lane
}

// sums[q] += t[q] * lambda for the first Used quantities; t holds each coefficient kLanes times.
// Used is a constant after inlining, so the sums stay in registers.
template <int Used>
inline void accumulate(Lanes (&sums)[kQuantityCount], const double* t, Lanes lambda) {
  for (int q = 0; q < Used; ++q) sums[q] += load(t + q * kLanes) * lambda;
}

// Adds the order-m terms of the first MaxUsed quantities for the lanes at `lane`: the sums over
// l = m..degree of t_q(l, +-m) Lambda_l^m (Part 0: cosine coefficients, 1: sine), times `factor`
// (Re or Im of (x + i y)^m). Quantity q reaches degree - (0, 1, 1, 1, 2, 2, ...): the value L,
// the gradient L - 1, the Hessian L - 2.
template <int MaxUsed, int Part>
inline void addOrder(const double* record, const double* lambdaRows, int m, int degree, int lane,
                     Lanes factor, SupportBlockValues& out) {
  constexpr int size = SupportEvaluator::kRecordSize;
  constexpr int offset = (2 + Part * kQuantityCount) * kLanes;
  constexpr int gradientUsed = MaxUsed < 4 ? MaxUsed : 4;
  Lanes sums[kQuantityCount];
  for (int q = 0; q < kQuantityCount; ++q) sums[q] = splat(0.0);
  int l = m;
  const double* t = record + offset;
  const double* lambda = lambdaRows + lane;
  for (; l + 2 <= degree; ++l, t += size, lambda += kSupportBlock) {
    accumulate<MaxUsed>(sums, t, load(lambda));
  }
  if (l + 1 == degree) {
    accumulate<gradientUsed>(sums, t, load(lambda));
    ++l, t += size, lambda += kSupportBlock;
  }
  accumulate<1>(sums, t, load(lambda));  // l == degree
  for (int q = 0; q < MaxUsed; ++q) {
    store(&out.values[q][lane], load(&out.values[q][lane]) + sums[q] * factor);
  }
}

template <int MaxUsed>
void evaluateLanes(const SupportEvaluator& evaluator, int padded, const double* x, const double* y,
                   const double* z, SupportBlockValues& out) {
  const int degree = evaluator.degree;
  constexpr int size = SupportEvaluator::kRecordSize;
  // lambdaRows[(l - m) * kSupportBlock + i]: Lambda_l^m at normal i for the current order m.
  alignas(16) double lambdaRows[(kMaxSupportDegree + 1) * kSupportBlock];
  alignas(16) double re[kSupportBlock];
  alignas(16) double im[kSupportBlock];
  for (int q = 0; q < MaxUsed; ++q) std::fill(out.values[q], out.values[q] + padded, 0.0);
  for (int i = 0; i < padded; ++i) {
    re[i] = 1.0;
    im[i] = 0.0;
  }
  for (int m = 0; m <= degree; ++m) {
    const double* record =
        evaluator.records.data() + evaluator.recordOffset[static_cast<std::size_t>(m)];
    // The recurrence in l, row by row for all normals (independent lanes, so it runs at full
    // throughput rather than at the latency of one normal's recurrence).
    const Lanes sectoral = load(record);  // Lambda_m^m
    for (int i = 0; i < padded; i += kLanes) {
      if (m > 0) {
        const Lanes lx = load(x + i), ly = load(y + i);
        const Lanes r = load(re + i), s = load(im + i);
        store(re + i, r * lx - s * ly);
        store(im + i, r * ly + s * lx);
      }
      store(lambdaRows + i, sectoral);
    }
    const double* t = record;
    for (int row = 1; row <= degree - m; ++row) {
      t += size;
      const Lanes a = load(t);
      const Lanes b = load(t + kLanes);
      double* current = lambdaRows + row * kSupportBlock;
      const double* previous = current - kSupportBlock;
      for (int i = 0; i < padded; i += kLanes) {
        const Lanes beforePrevious = row >= 2 ? load(previous - kSupportBlock + i) : splat(0.0);
        store(current + i, a * load(z + i) * load(previous + i) - b * beforePrevious);
      }
    }
    for (int i = 0; i < padded; i += kLanes) {
      addOrder<MaxUsed, 0>(record, lambdaRows, m, degree, i, load(re + i), out);
      if (m > 0) addOrder<MaxUsed, 1>(record, lambdaRows, m, degree, i, load(im + i), out);
    }
  }
}

}  // namespace

void SupportEvaluator::evaluateBlock(int count, const Eigen::Vector3d* normals,
                                     SupportBlockValues& out, bool pointsOnly) const {
  // Padded to whole lanes with the north pole; each lane's arithmetic involves its normal only.
  alignas(16) double x[kSupportBlock];
  alignas(16) double y[kSupportBlock];
  alignas(16) double z[kSupportBlock];
  const int padded = (count + kLanes - 1) / kLanes * kLanes;
  for (int i = 0; i < padded; ++i) {
    const bool real = i < count;
    x[i] = real ? normals[i].x() : 0.0;
    y[i] = real ? normals[i].y() : 0.0;
    z[i] = real ? normals[i].z() : 1.0;
  }
  if (pointsOnly) {
    evaluateLanes<kGradZ + 1>(*this, padded, x, y, z, out);
  } else {
    evaluateLanes<kQuantityCount>(*this, padded, x, y, z, out);
  }
}

void tangentFrame(const Eigen::Vector3d& n, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
  const double sign = std::copysign(1.0, n.z());
  const double a = -1.0 / (sign + n.z());
  const double b = n.x() * n.y() * a;
  e1 = Eigen::Vector3d(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  e2 = Eigen::Vector3d(b, sign + n.y() * n.y() * a, -n.y());
}

SupportPoint assembleSupportPoint(const Eigen::Vector3d& n, const SupportBlockValues& block,
                                  int i) {
  const auto at = [&](int q) { return block.values[q][i]; };
  SupportPoint sp;
  sp.normal = n;
  sp.value = at(kValue);
  const Eigen::Vector3d gradient(at(kGradX), at(kGradY), at(kGradZ));
  const double radial = n.dot(gradient);
  // P - n . grad P: the term of Hess_S h + h I besides the projected Hessian of P.
  const double defect = sp.value - radial;
  sp.surfaceGradient = gradient - radial * n;
  sp.point = sp.value * n + sp.surfaceGradient;
  Eigen::Matrix3d hessian;
  const double xx = at(kHessXX);
  const double xy = at(kHessXY);
  const double xz = at(kHessXZ);
  const double yy = at(kHessYY);
  const double yz = at(kHessYZ);
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
  const double half = 0.5 * (p - s);
  const double radius = std::sqrt(half * half + q * q);
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
  // Eigenvector of the larger eigenvalue, (cos t, sin t) in (e1, e2) with t = atan2(q, half) / 2
  // in (-pi/2, pi/2], from the half-angle formulas: cos t = sqrt((1 + cos 2t) / 2) with
  // cos 2t = half / radius, and sin t = q / (2 radius cos t).
  double c = 1.0;
  double sn = 0.0;
  if (radius > 0.0) {
    const double cosDouble = half / radius;
    if (cosDouble > -0.5) {
      c = std::sqrt(0.5 * (1.0 + cosDouble));
      sn = q / (2.0 * radius * c);
    } else {  // near t = +-pi/2: sin t from the other half-angle formula, sign of q (or +)
      const double magnitude = std::sqrt(0.5 * (1.0 - cosDouble));
      sn = std::signbit(q) ? -magnitude : magnitude;
      c = std::abs(q) / (2.0 * radius * magnitude);
    }
  }
  sp.direction2 = c * e1 + sn * e2;
  sp.direction1 = sp.direction2.cross(n);  // (direction1, direction2, n) right-handed
  return sp;
}

}  // namespace detail

namespace {

// The unit vector of `normal`; the message is only built on failure (this runs per normal).
Eigen::Vector3d normalized(const Eigen::Vector3d& normal) {
  const double length = normal.norm();
  if (std::isfinite(length) && length > 1e-100) return normal / length;
  return unitNormalOrThrow(normal, "the normal (" + std::to_string(normal.x()) + ", " +
                                       std::to_string(normal.y()) + ", " +
                                       std::to_string(normal.z()) + ")");
}

std::vector<Eigen::Vector3d> normalizedAll(const std::vector<Eigen::Vector3d>& normals) {
  std::vector<Eigen::Vector3d> unit(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double length = normals[i].norm();
    unit[i] = std::isfinite(length) && length > 1e-100
                  ? Eigen::Vector3d(normals[i] / length)
                  : unitNormalOrThrow(normals[i], "normal " + std::to_string(i));
  }
  return unit;
}

// Runs `body(blockBegin, count, values)` over fixed blocks of kSupportBlock normals in parallel;
// each task owns its scratch values.
template <typename Body>
void forEachBlock(std::size_t total, const Body& body) {
  const std::size_t blocks = (total + detail::kSupportBlock - 1) / detail::kSupportBlock;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 4),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      detail::SupportBlockValues values;
                      for (std::size_t block = range.begin(); block != range.end(); ++block) {
                        const std::size_t begin = block * detail::kSupportBlock;
                        const int count = static_cast<int>(
                            std::min<std::size_t>(detail::kSupportBlock, total - begin));
                        body(begin, count, values);
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

SupportFunction SupportFunction::sphere(const Eigen::Vector3d& center, double radius, int degree) {
  if (degree < 1 || degree > kMaxSupportDegree) {
    throw InputError("a sphere's support function needs a degree from 1 to " +
                     std::to_string(kMaxSupportDegree) + ", got " + std::to_string(degree));
  }
  if (!std::isfinite(radius)) throw InputError("the sphere's radius is not finite");
  SupportFunction zero(degree, Eigen::VectorXd::Zero(harmonicCount(degree)));
  return zero.offset(radius).translated(center);
}

double SupportFunction::value(const Eigen::Vector3d& normal) const {
  const Eigen::VectorXd basis = evaluateHarmonics(degree_, normalized(normal));
  return basis.dot(coefficients_);
}

Eigen::Vector3d SupportFunction::point(const Eigen::Vector3d& normal, double offset) const {
  const SupportPoint sp = evaluate(normal);
  return sp.point + offset * sp.normal;
}

SupportPoint SupportFunction::evaluate(const Eigen::Vector3d& normal) const {
  const Eigen::Vector3d n = normalized(normal);
  detail::SupportBlockValues values;
  evaluator_->evaluateBlock(1, &n, values, false);
  return detail::assembleSupportPoint(n, values, 0);
}

std::vector<SupportPoint> SupportFunction::evaluate(
    const std::vector<Eigen::Vector3d>& normals) const {
  const std::vector<Eigen::Vector3d> unit = normalizedAll(normals);
  std::vector<SupportPoint> out(unit.size());
  forEachBlock(unit.size(), [&](std::size_t begin, int count, detail::SupportBlockValues& values) {
    evaluator_->evaluateBlock(count, unit.data() + begin, values, false);
    for (int i = 0; i < count; ++i) {
      out[begin + static_cast<std::size_t>(i)] =
          detail::assembleSupportPoint(unit[begin + static_cast<std::size_t>(i)], values, i);
    }
  });
  return out;
}

std::vector<Eigen::Vector3d> SupportFunction::points(const std::vector<Eigen::Vector3d>& normals,
                                                     double offset) const {
  if (!std::isfinite(offset)) throw InputError("the offset distance is not finite");
  const std::vector<Eigen::Vector3d> unit = normalizedAll(normals);
  std::vector<Eigen::Vector3d> out(unit.size());
  forEachBlock(unit.size(), [&](std::size_t begin, int count, detail::SupportBlockValues& values) {
    evaluator_->evaluateBlock(count, unit.data() + begin, values, true);
    for (int i = 0; i < count; ++i) {
      const Eigen::Vector3d& n = unit[begin + static_cast<std::size_t>(i)];
      const Eigen::Vector3d gradient(values.values[detail::kGradX][i],
                                     values.values[detail::kGradY][i],
                                     values.values[detail::kGradZ][i]);
      const double h = values.values[detail::kValue][i] + offset;
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
