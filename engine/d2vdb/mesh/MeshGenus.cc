#include "d2vdb/mesh/MeshGenus.h"

namespace d2vdb {

bool isClosedOrientedManifold(const MeshReport& report) {
  return report.closed && report.manifold && report.oriented;
}

std::optional<long> surfaceGenus(const MeshReport& report) {
  if (!isClosedOrientedManifold(report)) return std::nullopt;
  const long twiceGenus =
      2 * static_cast<long>(report.connectedComponentCount) - report.eulerCharacteristic;
  return twiceGenus / 2;
}

}  // namespace d2vdb
