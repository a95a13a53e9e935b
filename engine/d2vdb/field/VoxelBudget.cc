#include "d2vdb/field/VoxelBudget.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/MathConstants.h"
#include "d2vdb/core/ResourceBudget.h"

namespace d2vdb {

double voxelSizeForBox(double longestSide, double voxelSize, int resolution,
                       const std::string& what) {
  if (voxelSize > 0) return voxelSize;
  if (!(longestSide > 0) || !std::isfinite(longestSide)) {
    throw InputError("the " + what +
                     " has a bounding box of zero extent, so a resolution cannot set the voxel "
                     "size; give a voxel size (--voxel-size)");
  }
  if (resolution <= 0) {
    throw InputError("the resolution (voxels along the longest side) must be positive, got " +
                     std::to_string(resolution));
  }
  return longestSide / resolution;
}
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Volume of the box with sides `sides` grown by r (Steiner's formula), and its terms.
struct BoxTerms {
  double volume, area, meanWidth;  // V_B, A_B, M_B = pi (a + b + c)
};

BoxTerms boxTerms(const std::array<double, 3>& sides) {
  const double a = sides[0], b = sides[1], c = sides[2];
  return {a * b * c, 2.0 * (a * b + b * c + c * a), kPi * (a + b + c)};
}

double grownBoxVolume(const BoxTerms& box, double r) {
  return box.volume + box.area * r + box.meanWidth * r * r + 4.0 / 3.0 * kPi * r * r * r;
}

bool known(const std::array<double, 3>& sides) {
  return sides[0] > 0.0 || sides[1] > 0.0 || sides[2] > 0.0;
}

// The band's volume in voxels (see estimateActiveVoxels), computed in voxel units so that neither
// tiny nor huge voxels overflow: lengths are divided by the voxel size h, the half-width w is
// already in voxels. The grown boxes take half a voxel more: a slab of width w holds up to w + 1
// layers of voxel centres.
double bandVoxels(const VoxelBudgetRequest& request, double h, double w) {
  const double g = w + 0.5;
  const auto scaled = [h](const std::array<double, 3>& sides) {
    return std::array<double, 3>{sides[0] / h, sides[1] / h, sides[2] / h};
  };
  const auto pieceVoxels = [&](double area, const std::array<double, 3>& sides) {
    const BoxTerms box = boxTerms(scaled(sides));
    const double sheet =
        2.0 * (area / h / h) * w + box.meanWidth * w * w + 4.0 / 3.0 * kPi * w * w * w;
    return known(sides) ? std::min(sheet, grownBoxVolume(box, g)) : sheet;
  };
  double voxels = 0.0;
  if (request.pieces.empty()) {
    voxels = pieceVoxels(request.surfaceArea, request.boxSides);
  } else {
    for (const SurfacePiece& piece : request.pieces)
      voxels += pieceVoxels(piece.area, piece.boxSides);
  }
  if (known(request.boxSides)) {
    voxels = std::min(voxels, grownBoxVolume(boxTerms(scaled(request.boxSides)), g));
  }
  return voxels;
}

double estimateAt(const VoxelBudgetRequest& request, double voxelSize, double halfWidth) {
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) return kInfinity;
  return bandVoxels(request, voxelSize, halfWidth) * kActiveVoxelSafetyFactor;
}

// The largest half-width (voxels) whose estimate at the request's voxel size fits, or 0.
double largestHalfWidthWithinBudget(const VoxelBudgetRequest& request) {
  const double limit = static_cast<double>(request.maxActiveVoxels);
  if (!(estimateAt(request, request.voxelSize, 1.0) <= limit)) return 0.0;
  double fits = 1.0, fails = std::max(request.halfWidth, 2.0);
  for (int i = 0; i < 200 && fails - fits > 0.5; ++i) {
    const double middle = 0.5 * (fits + fails);
    (estimateAt(request, request.voxelSize, middle) <= limit ? fits : fails) = middle;
  }
  return std::floor(fits);
}

// A half-width for messages: "1000", "2.5".
std::string halfWidthText(double halfWidth) {
  std::ostringstream text;
  text.precision(6);
  text << halfWidth;
  return text.str();
}

// `value` rounded up to three significant digits, so that the printed advice is on the safe side.
double roundUp3(double value) {
  if (!(value > 0.0) || !std::isfinite(value)) return value;
  const double scale = std::pow(10.0, std::floor(std::log10(value)) - 2.0);
  return std::ceil(value / scale * (1.0 - 1e-12)) * scale;
}

}  // namespace

std::vector<SurfacePiece> surfacePieces(const TriangleMesh& mesh) {
  // Union-find over vertices, joined along each triangle's edges.
  std::vector<std::uint32_t> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), 0u);
  const auto find = [&parent](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const TriangleMesh::Triangle& t : mesh.triangles) {
    const std::uint32_t root = find(t[0]);
    parent[find(t[1])] = root;
    parent[find(t[2])] = find(root);
  }
  std::vector<std::int64_t> pieceOf(mesh.positions.size(), -1);
  std::vector<SurfacePiece> pieces;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const TriangleMesh::Triangle& t : mesh.triangles) {
    const std::uint32_t root = find(t[0]);
    if (pieceOf[root] < 0) {
      pieceOf[root] = static_cast<std::int64_t>(pieces.size());
      pieces.emplace_back();
      boxes.emplace_back();
    }
    const auto index = static_cast<std::size_t>(pieceOf[root]);
    const Eigen::Vector3d a = mesh.positions[t[0]].cast<double>();
    const Eigen::Vector3d b = mesh.positions[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh.positions[t[2]].cast<double>();
    pieces[index].area += 0.5 * (b - a).cross(c - a).norm();
    boxes[index].extend(a).extend(b).extend(c);
  }
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Eigen::Vector3d sides = boxes[i].sizes();
    pieces[i].boxSides = {sides.x(), sides.y(), sides.z()};
  }
  return pieces;
}

double estimateActiveVoxels(const VoxelBudgetRequest& request) {
  return estimateAt(request, request.voxelSize, request.halfWidth);
}

double minimumActiveVoxels(double halfWidth) {
  return kActiveVoxelSafetyFactor * 4.0 / 3.0 * kPi * halfWidth * halfWidth * halfWidth;
}

double smallestVoxelSizeWithinBudget(const VoxelBudgetRequest& request) {
  const double limit = static_cast<double>(request.maxActiveVoxels);
  if (!(minimumActiveVoxels(request.halfWidth) < limit)) return kInfinity;
  // The estimate falls monotonically with the voxel size: bracket, then bisect geometrically.
  double fits =
      request.voxelSize > 0.0 && std::isfinite(request.voxelSize) ? request.voxelSize : 1.0;
  double fails = fits;
  while (estimateAt(request, fits, request.halfWidth) > limit) {
    fails = fits;
    fits *= 2.0;
    if (!std::isfinite(fits)) return kInfinity;
  }
  if (fails == fits) {
    while (fails > 1e-300 && estimateAt(request, fails, request.halfWidth) <= limit) {
      fits = fails;
      fails *= 0.5;
    }
  }
  for (int i = 0; i < 100 && fits > fails * (1.0 + 1e-12); ++i) {
    const double middle = std::sqrt(fits * fails);
    (estimateAt(request, middle, request.halfWidth) <= limit ? fits : fails) = middle;
  }
  return fits;
}

void checkVoxelSizeIsRepresentable(double voxelSize, const std::string& subject) {
  if (std::isfinite(voxelSize) && voxelSize >= kMinimumVoxelSize) return;
  std::ostringstream message;
  message.precision(3);
  message << subject << ": the voxel size " << voxelSize;
  if (!(voxelSize > 0.0) || !std::isfinite(voxelSize)) {
    message << " is not a positive finite number";
  } else {
    message << " is below " << kMinimumVoxelSize
            << " world units, the smallest voxel an OpenVDB grid can have (its transforms refuse "
               "voxel volumes below 3e-15); use a larger --voxel-size or a lower --resolution, or "
               "express the geometry in smaller units (e.g. millimetres instead of metres)";
  }
  throw InputError(message.str());
}

double estimateBandMemoryBytes(const VoxelBudgetRequest& request) {
  return request.fixedBytes + request.bytesPerVoxel * estimateActiveVoxels(request);
}

void enforceVoxelBudget(const VoxelBudgetRequest& original) {
  // The memory budget, when it binds before the voxel limit, becomes the voxel limit.
  VoxelBudgetRequest request = original;
  bool memoryBinds = false;
  if (original.bytesPerVoxel > 0.0 && original.maxMemoryBytes > 0) {
    const double byMemory =
        std::max(0.0, (static_cast<double>(original.maxMemoryBytes) - original.fixedBytes) /
                          original.bytesPerVoxel);
    if (byMemory < static_cast<double>(original.maxActiveVoxels)) {
      request.maxActiveVoxels = static_cast<std::uint64_t>(byMemory);
      memoryBinds = true;
    }
  }
  const double estimate = estimateActiveVoxels(request);
  if (estimate <= static_cast<double>(request.maxActiveVoxels)) {
    // Within the budget; the voxel can still be too small for OpenVDB (a tiny shape).
    checkVoxelSizeIsRepresentable(request.voxelSize, request.subject);
    return;
  }

  std::ostringstream message;
  message.precision(3);
  message << request.subject << " at voxel size " << request.voxelSize << " would need about "
          << estimate << " active voxels (half-width " << halfWidthText(request.halfWidth)
          << " voxels)";
  if (memoryBinds) {
    message << ", about " << byteSizeText(estimateBandMemoryBytes(original)) << " of memory ("
            << original.bytesPerVoxel << " bytes per voxel), above the memory budget of "
            << byteSizeText(static_cast<double>(original.maxMemoryBytes)) << " (--max-memory)";
  } else {
    message << ", above the limit of " << static_cast<double>(request.maxActiveVoxels)
            << " active voxels";
  }
  std::vector<std::string> remedies;
  const double smallestVoxel = roundUp3(smallestVoxelSizeWithinBudget(request));
  if (std::isfinite(smallestVoxel)) {
    std::ostringstream remedy;
    remedy.precision(3);
    remedy << "a voxel size of at least " << smallestVoxel;
    const double resolution =
        request.longestSide > 0.0 ? std::floor(request.longestSide / smallestVoxel) : 0.0;
    if (resolution >= 1.0) {
      remedy << " (a resolution of at most " << static_cast<long long>(resolution)
             << " voxels along the longest side)";
    }
    remedies.push_back(remedy.str());
  } else {
    message << "; no voxel size fits: a band of " << halfWidthText(request.halfWidth)
            << " voxels on each side holds about " << minimumActiveVoxels(request.halfWidth)
            << " voxels at any voxel size";
  }
  const double halfWidth = largestHalfWidthWithinBudget(request);
  if (halfWidth >= 1.0) {
    remedies.push_back("a half-width of at most " +
                       std::to_string(static_cast<long long>(halfWidth)) + " voxels");
  } else if (!std::isfinite(smallestVoxel)) {
    remedies.push_back("a smaller half-width");
  }
  remedies.push_back(memoryBinds ? "a higher --max-memory if the machine has the memory"
                                 : "a higher active-voxel limit if the machine has the memory");
  message << "; use ";
  for (std::size_t i = 0; i < remedies.size(); ++i) {
    message << (i == 0 ? "" : i + 1 == remedies.size() ? " or " : ", ") << remedies[i];
  }
  throw InputError(message.str());
}

}  // namespace d2vdb
