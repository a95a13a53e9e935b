#include "d2vdb/measure/HausdorffShape.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/measure/detail/CertifiedDistance.h"
#include "d2vdb/spline/BezierPatch.h"

namespace d2vdb {
namespace {

/// The most primitives a tessellated spline may have (about 2.4 GB as points and triangles).
constexpr double kMaxTessellationPrimitives = 5e7;

/// Relative slack on the interpolation bounds for the rounding of the parameters i / n (the cells
/// are then off their nominal width by a few units in the last place).
constexpr double kParameterSlack = 1e-12;

void requireTolerance(double maxError, const char* what) {
  if (!(maxError >= 0.0) || !std::isfinite(maxError)) {
    throw InputError(std::string("the tessellation error of a ") + what +
                     " must be a finite number of world units >= 0, not " + formatNumber(maxError));
  }
}

void requireCount(double primitives, const char* what, double maxError) {
  if (primitives > kMaxTessellationPrimitives) {
    throw InputError(std::string("tessellating the ") + what + " to within " +
                     formatNumber(maxError) + " would need " + formatNumber(primitives) +
                     " primitives (at most 5e7): ask for a larger tolerance");
  }
}

double largestNorm(const std::vector<Eigen::Vector3d>& points) {
  double largest = 0.0;
  for (const Eigen::Vector3d& point : points) largest = std::max(largest, point.norm());
  return largest;
}

/// Bound on the rounding of a de Casteljau evaluation of total degree `degree` with control
/// points of norm <= `scale`: each of the `degree` levels of convex combinations adds at most 3u
/// of the largest magnitude per coordinate.
double evaluationRounding(int degree, double scale) {
  return 6.0 * (degree + 2) * detail::kUnitRoundoff * scale;
}

/// max_k |P_k+2 - 2 P_k+1 + P_k| over a row of control points (stride apart).
double largestSecondDifference(const std::vector<Eigen::Vector3d>& controls, int first, int count,
                               int stride) {
  double largest = 0.0;
  for (int k = 0; k + 2 < count; ++k) {
    const Eigen::Vector3d& p0 = controls[first + k * stride];
    const Eigen::Vector3d& p1 = controls[first + (k + 1) * stride];
    const Eigen::Vector3d& p2 = controls[first + (k + 2) * stride];
    largest = std::max(largest, (p2 - 2.0 * p1 + p0).norm());
  }
  return largest;
}

/// Bounds of |S_ss|, |S_st| and |S_tt| over a Bézier patch (convex hull of the derivatives'
/// control points).
struct SecondDerivativeBounds {
  double uu = 0.0, uv = 0.0, vv = 0.0;
};

SecondDerivativeBounds secondDerivativeBounds(const BezierPatch& patch) {
  const int p = patch.degreeU;
  const int q = patch.degreeV;
  const std::vector<Eigen::Vector3d>& controls = patch.controlPoints;
  SecondDerivativeBounds bounds;
  double uu = 0.0, vv = 0.0, uv = 0.0;
  for (int b = 0; b <= q; ++b)
    uu = std::max(uu, largestSecondDifference(controls, b, p + 1, q + 1));
  for (int a = 0; a <= p; ++a)
    vv = std::max(vv, largestSecondDifference(controls, a * (q + 1), q + 1, 1));
  for (int a = 0; a < p; ++a) {
    for (int b = 0; b < q; ++b) {
      const auto at = [&](int i, int j) -> const Eigen::Vector3d& {
        return controls[i * (q + 1) + j];
      };
      uv = std::max(uv, (at(a + 1, b + 1) - at(a + 1, b) - at(a, b + 1) + at(a, b)).norm());
    }
  }
  bounds.uu = p * (p - 1) * uu;
  bounds.vv = q * (q - 1) * vv;
  bounds.uv = p * q * uv;
  return bounds;
}

double interpolationError(const SecondDerivativeBounds& bounds, int cellsU, int cellsV) {
  const double hu = (1.0 + kParameterSlack) / cellsU;
  const double hv = (1.0 + kParameterSlack) / cellsV;
  return 0.5 * (hu * hu * bounds.uu + 2.0 * hu * hv * bounds.uv + hv * hv * bounds.vv);
}

/// The smallest grid (growing the direction that contributes more) that meets `maxError`.
std::pair<int, int> patchGrid(const SecondDerivativeBounds& bounds, double maxError) {
  int cellsU = 1, cellsV = 1;
  constexpr int kMaxCells = 1 << 16;
  while (interpolationError(bounds, cellsU, cellsV) > maxError) {
    const double uPart =
        bounds.uu / (double(cellsU) * cellsU) + bounds.uv / (double(cellsU) * cellsV);
    const double vPart =
        bounds.vv / (double(cellsV) * cellsV) + bounds.uv / (double(cellsU) * cellsV);
    // Grow by about 10% at a time: a few hundred steps at most.
    int& grow = uPart >= vPart ? cellsU : cellsV;
    grow = std::min(kMaxCells, grow + std::max(1, grow / 10));
    if (cellsU == kMaxCells && cellsV == kMaxCells) break;
  }
  return {cellsU, cellsV};
}

std::string describedTessellation(const char* what, double error) {
  std::ostringstream text;
  text << what << " tessellated to within " << formatNumber(error);
  return text.str();
}

}  // namespace

HausdorffShape hausdorffShapeOfMesh(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) throw InputError("the mesh has no triangles");
  HausdorffShape shape;
  shape.description = "mesh";
  shape.points.reserve(mesh.positions.size());
  for (const Eigen::Vector3f& position : mesh.positions) {
    if (!position.allFinite()) throw InputError("the mesh has a non-finite vertex position");
    shape.points.push_back(position.cast<double>());
  }
  for (const TriangleMesh::Triangle& triangle : mesh.triangles) {
    for (const TriangleMesh::Index corner : triangle) {
      if (corner >= mesh.positions.size()) {
        throw InputError("a triangle of the mesh names vertex " + std::to_string(corner) + " of " +
                         std::to_string(mesh.positions.size()));
      }
    }
  }
  shape.triangles = mesh.triangles;
  return shape;
}

HausdorffShape hausdorffShapeOfPoints(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) throw InputError("the point set is empty");
  HausdorffShape shape;
  shape.description = "points";
  shape.points = points;
  shape.triangles.reserve(points.size());
  for (std::size_t index = 0; index < points.size(); ++index) {
    if (!points[index].allFinite()) {
      throw InputError("point " + std::to_string(index) + " is not finite");
    }
    const auto corner = static_cast<TriangleMesh::Index>(index);
    shape.triangles.push_back({corner, corner, corner});
  }
  return shape;
}

HausdorffShape hausdorffShapeOfCurve(const BSplineCurve& curve, double maxError) {
  requireTolerance(maxError, "curve");
  const std::vector<BezierSegment> segments = curve.openRepresentation().toBezierSegments();
  HausdorffShape shape;
  for (const BezierSegment& segment : segments) {
    BezierNet net;
    net.degreeU = segment.curve.degree();
    for (int k = 0; k <= net.degreeU; ++k) net.controls.push_back(segment.curve.controlPoint(k));
    shape.nets.push_back(std::move(net));
  }
  if (maxError == 0.0) {
    shape.description = "B-spline curve (Bézier segments)";
    return shape;
  }
  std::vector<int> steps;
  double total = 0.0, rounding = 0.0;
  for (const BezierSegment& segment : segments) {
    const int p = segment.curve.degree();
    std::vector<Eigen::Vector3d> controls;
    for (int k = 0; k <= p; ++k) controls.push_back(segment.curve.controlPoint(k));
    const double second = p * (p - 1) * largestSecondDifference(controls, 0, p + 1, 1);
    // h^2 / 8 * second <= maxError.
    const double needed = std::ceil((1.0 + kParameterSlack) * std::sqrt(second / (8.0 * maxError)));
    total += std::max(1.0, needed);
    requireCount(total, "curve", maxError);
    steps.push_back(std::max(1, static_cast<int>(needed)));
    rounding = std::max(rounding, evaluationRounding(p, largestNorm(controls)));
  }
  shape.approximationError = maxError + rounding;
  shape.description = describedTessellation("B-spline curve", shape.approximationError);
  for (std::size_t piece = 0; piece < segments.size(); ++piece) {
    const auto first = static_cast<TriangleMesh::Index>(shape.points.size());
    for (int i = 0; i <= steps[piece]; ++i) {
      shape.points.push_back(segments[piece].curve.evaluate(double(i) / steps[piece]));
    }
    for (int i = 0; i < steps[piece]; ++i) {
      const TriangleMesh::Index from = first + i;
      shape.triangles.push_back({from, from + 1, from + 1});
    }
  }
  return shape;
}

HausdorffShape hausdorffShapeOfSurface(const BSplineSurface& surface, double maxError) {
  requireTolerance(maxError, "surface");
  const std::vector<BezierPatch> patches = toBezierPatches(surface);
  HausdorffShape shape;
  for (const BezierPatch& patch : patches) {
    shape.nets.push_back({patch.degreeU, patch.degreeV, patch.controlPoints});
  }
  if (maxError == 0.0) {
    shape.description = "B-spline surface (Bézier patches)";
    return shape;
  }
  // Each patch's grid, the error it reaches and the count, all before anything is allocated.
  std::vector<std::pair<int, int>> grids;
  double total = 0.0, rounding = 0.0, reached = 0.0;
  for (const BezierPatch& patch : patches) {
    const SecondDerivativeBounds bounds = secondDerivativeBounds(patch);
    grids.push_back(patchGrid(bounds, maxError));
    reached =
        std::max(reached, interpolationError(bounds, grids.back().first, grids.back().second));
    total += 2.0 * grids.back().first * grids.back().second;
    requireCount(total, "surface", maxError);
    rounding = std::max(rounding, evaluationRounding(patch.degreeU + patch.degreeV,
                                                     largestNorm(patch.controlPoints)));
  }
  if (reached > maxError) {
    throw InputError("a Bézier patch of the surface cannot be tessellated to within " +
                     formatNumber(maxError) + " (65536 cells a side reach " +
                     formatNumber(reached) + "): ask for a larger tolerance");
  }
  for (std::size_t piece = 0; piece < patches.size(); ++piece) {
    const int cellsU = grids[piece].first;
    const int cellsV = grids[piece].second;
    const auto first = static_cast<TriangleMesh::Index>(shape.points.size());
    for (int i = 0; i <= cellsU; ++i) {
      for (int j = 0; j <= cellsV; ++j) {
        shape.points.push_back(patches[piece].evaluate(double(i) / cellsU, double(j) / cellsV));
      }
    }
    const auto at = [&](int i, int j) {
      return first + static_cast<TriangleMesh::Index>(i * (cellsV + 1) + j);
    };
    for (int i = 0; i < cellsU; ++i) {
      for (int j = 0; j < cellsV; ++j) {
        shape.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        shape.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
    }
  }
  shape.approximationError = reached + rounding;
  shape.description = describedTessellation("B-spline surface", shape.approximationError);
  return shape;
}

double combinedDiagonal(const HausdorffShape& a, const HausdorffShape& b) {
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (const HausdorffShape* shape : {&a, &b}) {
    for (const Eigen::Vector3d& point : shape->points) {
      low = low.cwiseMin(point);
      high = high.cwiseMax(point);
    }
  }
  return (a.points.empty() && b.points.empty()) ? 0.0 : (high - low).norm();
}

}  // namespace d2vdb
