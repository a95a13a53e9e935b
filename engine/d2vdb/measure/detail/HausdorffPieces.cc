#include "d2vdb/measure/detail/HausdorffPieces.h"

#include <algorithm>
#include <limits>

#include "d2vdb/measure/detail/CertifiedDistance.h"

namespace d2vdb::detail {
namespace {

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

/// min over the corners of corner bound + the farthest hull point from the corner, rounded up.
double lipschitzOver(const Eigen::Vector3d* hull, int hullCount, const Eigen::Vector3d* corners,
                     const double* cornerUpper, int cornerCount) {
  double best = kUnbounded;
  for (int k = 0; k < cornerCount; ++k) {
    double extent = 0.0;
    for (int j = 0; j < hullCount; ++j) extent = std::max(extent, (hull[j] - corners[k]).norm());
    best = std::min(best, (cornerUpper[k] + extent) * (1.0 + 8.0 * kUnitRoundoff));
  }
  return best;
}

/// de Casteljau at 1/2 of the `count` points first, first + stride, ...: the two halves.
void halve(const std::vector<Eigen::Vector3d>& controls, int first, int count, int stride,
           std::vector<Eigen::Vector3d>& low, std::vector<Eigen::Vector3d>& high, int outFirst,
           int outStride) {
  std::array<Eigen::Vector3d, 32> work;
  for (int k = 0; k < count; ++k) work[k] = controls[first + k * stride];
  for (int level = 0; level < count; ++level) {
    low[outFirst + level * outStride] = work[0];
    high[outFirst + (count - 1 - level) * outStride] = work[count - 1 - level];
    for (int k = 0; k + 1 < count - level; ++k) work[k] = 0.5 * (work[k] + work[k + 1]);
  }
}

}  // namespace

double TrianglePiece::lipschitzUpper() const {
  return lipschitzOver(corners.data(), cornerCount, corners.data(), cornerUpper.data(),
                       cornerCount);
}

void TrianglePiece::split(TrianglePiece* children, const CornerBound& bound) const {
  const auto make = [&](int index, const std::array<Eigen::Vector3d, 3>& childCorners,
                        const std::array<double, 3>& uppers) {
    TrianglePiece& child = children[index];
    child.corners = childCorners;
    child.cornerUpper = uppers;
    child.cornerCount = cornerCount;
    child.depth = static_cast<std::uint8_t>(depth + 1);
  };
  const std::array<Eigen::Vector3d, 3>& c = corners;
  const std::array<double, 3>& d = cornerUpper;
  if (cornerCount == 2) {
    const Eigen::Vector3d middle = 0.5 * (c[0] + c[1]);
    const double m = bound(middle);
    make(0, {c[0], middle, middle}, {d[0], m, m});
    make(1, {middle, c[1], c[1]}, {m, d[1], d[1]});
    return;
  }
  const Eigen::Vector3d ab = 0.5 * (c[0] + c[1]);
  const Eigen::Vector3d bc = 0.5 * (c[1] + c[2]);
  const Eigen::Vector3d ca = 0.5 * (c[2] + c[0]);
  const double mab = bound(ab), mbc = bound(bc), mca = bound(ca);
  make(0, {c[0], ab, ca}, {d[0], mab, mca});
  make(1, {ab, c[1], bc}, {mab, d[1], mbc});
  make(2, {ca, bc, c[2]}, {mca, mbc, d[2]});
  make(3, {ab, bc, ca}, {mab, mbc, mca});
}

TrianglePiece trianglePiece(const HausdorffShape& from, const TriangleIndices& triangle,
                            const std::vector<double>& pointUpper) {
  std::array<std::uint32_t, 3> corners = {triangle[0], triangle[1], triangle[2]};
  const auto same = [&](std::uint32_t i, std::uint32_t j) {
    return from.points[i] == from.points[j];
  };
  TrianglePiece piece;
  if (same(corners[0], corners[1]) && same(corners[1], corners[2])) {
    piece.cornerCount = 1;
  } else if (same(corners[0], corners[1]) || same(corners[1], corners[2]) ||
             same(corners[0], corners[2])) {
    piece.cornerCount = 2;
    if (same(corners[0], corners[1])) corners[1] = corners[2];
    corners[2] = corners[1];
  }
  for (int k = 0; k < 3; ++k) {
    piece.corners[k] = from.points[corners[k]];
    piece.cornerUpper[k] = pointUpper[corners[k]];
  }
  return piece;
}

Eigen::Vector3d NetPiece::corner(int k) const {
  const int p = degreeU, q = degreeV;
  const int a = (k & 1) ? p : 0;
  const int b = (k & 2) ? q : 0;
  return controls[a * (q + 1) + b];
}

double NetPiece::lipschitzUpper() const {
  std::array<Eigen::Vector3d, 4> corners;
  for (int k = 0; k < cornerCount(); ++k) corners[k] = corner(k);
  return lipschitzOver(controls.data(), hullCount(), corners.data(), cornerUpper.data(),
                       cornerCount());
}

void NetPiece::split(NetPiece* children, const CornerBound& bound) const {
  const int p = degreeU, q = degreeV;
  for (int c = 0; c < childCount(); ++c) {
    children[c].controls.resize(controls.size());
    children[c].degreeU = degreeU;
    children[c].degreeV = degreeV;
    children[c].depth = static_cast<std::uint8_t>(depth + 1);
  }
  if (q == 0) {
    halve(controls, 0, p + 1, 1, children[0].controls, children[1].controls, 0, 1);
    const double middle = bound(children[0].corner(1));
    children[0].cornerUpper = {cornerUpper[0], middle, 0.0, 0.0};
    children[1].cornerUpper = {middle, cornerUpper[1], 0.0, 0.0};
    return;
  }
  // Halve every column in u, then every row of each half in v.
  std::vector<Eigen::Vector3d> lowU(controls.size()), highU(controls.size());
  for (int b = 0; b <= q; ++b) halve(controls, b, p + 1, q + 1, lowU, highU, b, q + 1);
  for (int a = 0; a <= p; ++a) {
    halve(lowU, a * (q + 1), q + 1, 1, children[0].controls, children[2].controls, a * (q + 1), 1);
    halve(highU, a * (q + 1), q + 1, 1, children[1].controls, children[3].controls, a * (q + 1), 1);
  }
  // The five new corner points: the middles of the four sides and the centre.
  const double sideV0 = bound(children[0].corner(1));  // u = 1/2, v = 0
  const double sideU0 = bound(children[0].corner(2));  // u = 0, v = 1/2
  const double centre = bound(children[0].corner(3));
  const double sideU1 = bound(children[1].corner(3));  // u = 1, v = 1/2
  const double sideV1 = bound(children[2].corner(3));  // u = 1/2, v = 1
  children[0].cornerUpper = {cornerUpper[0], sideV0, sideU0, centre};
  children[1].cornerUpper = {sideV0, cornerUpper[1], centre, sideU1};
  children[2].cornerUpper = {sideU0, centre, cornerUpper[2], sideV1};
  children[3].cornerUpper = {centre, sideU1, sideV1, cornerUpper[3]};
}

NetPiece netPiece(const BezierNet& net) {
  NetPiece piece;
  piece.controls = net.controls;
  piece.degreeU = static_cast<std::uint8_t>(net.degreeU);
  piece.degreeV = static_cast<std::uint8_t>(net.degreeV);
  piece.cornerUpper.fill(kUnbounded);
  return piece;
}

}  // namespace d2vdb::detail
