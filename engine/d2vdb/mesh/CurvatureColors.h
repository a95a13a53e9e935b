// Per-vertex principal curvatures as mesh attributes, coloured by mean curvature, with the
// ranges and percentiles a report states.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb {

/// The value at fraction q (0..1, clamped) of the sorted values, by nearest rank; 0 for no values.
double nearestRankQuantile(std::vector<double> values, double q);

/// What curvatureAttributes() measured (1 / world units).
struct CurvatureSummary {
  std::array<double, 2> k1Range{0.0, 0.0};               ///< min, max of k1
  std::array<double, 2> k2Range{0.0, 0.0};               ///< min, max of k2
  std::array<double, 2> meanRange{0.0, 0.0};             ///< min, max of H = (k1 + k2) / 2
  std::array<double, 3> meanPercentiles{0.0, 0.0, 0.0};  ///< H at 1 %, 50 %, 99 %
  double colorScale = 0.0;  ///< the 99th percentile of |H|: the colour scale
};

/// Vertex attributes and their summary.
struct CurvatureAttributes {
  VertexAttributes attributes;
  CurvatureSummary summary;
};

/// The attributes of a mesh whose vertices have principal curvatures k1 >= k2: scalars "k1" and
/// "k2" (PLY properties, float) and the colour of each vertex's H against the 99th percentile of
/// |H| (distanceColor(): red convex, bending away from the outward normal; white flat; blue
/// concave). All zeros for no vertices. Throws InputError when k1 and k2 differ in size
/// or hold a non-finite value.
CurvatureAttributes curvatureAttributes(const std::vector<double>& k1,
                                        const std::vector<double>& k2);

}  // namespace d2vdb
