#include "d2vdb/support/SupportOffsets.h"

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"
#include "d2vdb/support/SupportTessellation.h"

namespace d2vdb {

void requireRegularOffsets(const SupportValidity& validity, const std::vector<double>& distances,
                           bool allowSingular, std::vector<std::string>& warnings) {
  if (!validity.regular()) return;
  for (const double d : distances) {
    try {
      requireRegularOffset(validity, d);
    } catch (const InputError& error) {
      if (!allowSingular) {
        throw InputError(std::string(error.what()) +
                         "; choose a distance inside the safe range or pass --allow-singular");
      }
      warnings.push_back(std::string(error.what()) + " (kept: --allow-singular)");
    }
  }
}

void requireRegularPatchOffsets(const SupportPatchSet& set, const std::vector<double>& distances,
                                bool allowSingular, std::vector<std::string>& warnings) {
  const double lo = set.safeOffsetMin();
  const double hi = set.safeOffsetMax();
  for (const double d : distances) {
    if (d > lo && d < hi) continue;
    const std::string message =
        "offset " + formatNumber(d, 6) + " is outside the range (" + formatNumber(lo, 6) + ", " +
        formatNumber(hi, 6) +
        ") where every patch stays regular (a principal radius r + d would change sign: cusps or "
        "self-intersections)";
    if (!allowSingular) {
      throw InputError(message + "; choose a distance inside it or pass --allow-singular");
    }
    warnings.push_back(message + " (kept: --allow-singular)");
  }
}

SphericalTriangulation tessellationDomain(const std::optional<SphericalTriangulation>& patch,
                                          int subdivisions) {
  return patch ? *patch : geodesicSphere(subdivisions);
}

TriangleMesh tessellatePatchOffsets(const SupportPatchSet& set, double distance) {
  TriangleMesh mesh;
  for (const SupportPatch& p : set.patches) {
    const TriangleMesh piece = tessellateSupport(p.function, p.gaussImage.gaussImage, distance);
    const auto base = static_cast<TriangleMesh::Index>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), piece.positions.begin(), piece.positions.end());
    mesh.normals.insert(mesh.normals.end(), piece.normals.begin(), piece.normals.end());
    for (const auto& t : piece.triangles) {
      mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
  }
  return mesh;
}

}  // namespace d2vdb
