#include "d2vdb/support/SupportOffsets.h"

#include <cmath>

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

std::array<double, 2> tessellationDomainSize(const std::optional<SphericalTriangulation>& patch,
                                             int subdivisions) {
  if (patch) {
    return {static_cast<double>(patch->normals.size()),
            static_cast<double>(patch->triangles.size())};
  }
  const double cells = std::ldexp(1.0, 2 * subdivisions);  // 4^s
  return {10.0 * cells + 2.0, 20.0 * cells};
}

namespace {

struct OffsetCosts {
  double memoryBytes = 0.0;
  double fileBytes = 0.0;
};

OffsetCosts supportOffsetCosts(const std::optional<SphericalTriangulation>& patch, int subdivisions,
                               std::size_t count, const std::optional<MeshFormat>& format,
                               double bytesPerTriangle) {
  const auto [vertices, triangles] = tessellationDomainSize(patch, subdivisions);
  const double offsets = static_cast<double>(count);
  OffsetCosts costs;
  costs.memoryBytes = kSupportOffsetBytesPerVertex * vertices + bytesPerTriangle * triangles;
  if (format) {
    costs.memoryBytes += offsets * (24.0 * vertices + 12.0 * triangles);
    MeshFileContents contents;
    contents.normals = true;
    costs.fileBytes = offsets * estimateMeshFileBytes(*format, vertices, triangles, contents);
  }
  return costs;
}

}  // namespace

void enforceSupportOffsetBudget(const std::optional<SphericalTriangulation>& patch,
                                int subdivisions, std::size_t count,
                                const std::optional<MeshFormat>& format, double bytesPerTriangle,
                                const ResourceBudget& budget) {
  const auto fits = [&](long long s) {
    const OffsetCosts costs =
        supportOffsetCosts(patch, static_cast<int>(s), count, format, bytesPerTriangle);
    return (budget.maxMemoryBytes == 0 ||
            costs.memoryBytes <= static_cast<double>(budget.maxMemoryBytes)) &&
           (budget.maxOutputBytes == 0 ||
            costs.fileBytes <= static_cast<double>(budget.maxOutputBytes));
  };
  if (fits(subdivisions)) return;
  const auto [vertices, triangles] = tessellationDomainSize(patch, subdivisions);
  BudgetRequest request;
  request.subject =
      std::to_string(count) + (count == 1 ? " offset" : " offsets") + " over " +
      (patch ? std::string("the patch's Gauss image")
             : "a geodesic sphere of --subdivisions " + std::to_string(subdivisions)) +
      " (" + std::to_string(static_cast<long long>(vertices)) + " vertices, " +
      std::to_string(static_cast<long long>(triangles)) + " triangles each)";
  if (!patch) {
    const long long fitting = largestFitting(0, subdivisions, fits);
    request.remedy = fitting >= 0 ? "use --subdivisions " + std::to_string(fitting) + " or fewer"
                                  : "use fewer --distance values";
  }
  const OffsetCosts costs =
      supportOffsetCosts(patch, subdivisions, count, format, bytesPerTriangle);
  request.estimatedBytes = costs.fileBytes;
  enforceOutputBudget(request, budget);
  request.estimatedBytes = costs.memoryBytes;
  enforceMemoryBudget(request, budget);
}

}  // namespace d2vdb
