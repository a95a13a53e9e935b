#include "d2vdb/mesh/DistanceColors.h"

#include <algorithm>
#include <cmath>

namespace d2vdb {

std::array<std::uint8_t, 3> distanceColor(double distance, double scale) {
  const double t = scale > 0.0 ? std::clamp(distance / scale, -1.0, 1.0) : 0.0;
  const auto channel = [](double value) {
    return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(value, 0.0, 1.0)));
  };
  return t >= 0.0 ? std::array<std::uint8_t, 3>{255, channel(1.0 - t), channel(1.0 - t)}
                  : std::array<std::uint8_t, 3>{channel(1.0 + t), channel(1.0 + t), 255};
}

VertexAttributes distanceAttributes(const TriangleMesh& mesh,
                                    const std::function<double(const Eigen::Vector3d&)>& distance,
                                    double& largest) {
  VertexAttributes attributes;
  attributes.scalarName = "distance";
  largest = 0.0;
  for (const Eigen::Vector3f& p : mesh.positions) {
    double d = distance(p.cast<double>());
    if (!std::isfinite(d)) d = 0.0;
    attributes.scalars.push_back(static_cast<float>(d));
    largest = std::max(largest, std::abs(d));
  }
  const double scale = largest > 0.0 ? largest : 1.0;
  for (const float d : attributes.scalars) attributes.colors.push_back(distanceColor(d, scale));
  return attributes;
}

}  // namespace d2vdb
