// The surface estimator as first written: voxel by voxel, straight from its definition (see
// SurfaceEstimatorReference.h). Kept unoptimised on purpose, as the reference of the library's
// estimator.
#include "SurfaceEstimatorReference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "d2vdb/field/detail/LeafTable.h"

namespace d2vdb::test {
namespace {

using namespace d2vdb::detail;

using LeafT = openvdb::FloatGrid::TreeType::LeafNodeType;

constexpr double kNearSurface = 1.75;     // voxels: where pass 1 fits the quadric
constexpr double kMinimumGradient = 0.7;  // |grad d| below this: a kink (cut locus)
constexpr double kMinimumFocal = 0.05;    // 1 + d k below this: near a centre of curvature
/// Footpoint iterations stop once a round moves the footpoint by less than this (voxels). The
/// rounds contract by about |d| k per round, so the footpoint left is within a few thousandths of a
/// voxel of the converged one, and the interpolated Hessian changes by O(this) times its gradient:
/// on the test sphere and torus the measured errors are those of full convergence (1e-4 voxel,
/// 2.1 interpolations per voxel on the bunny; this one 1.2).
constexpr double kFootpointStep = 0.02;
/// Trilinear weight of the corners with a full stencil below which an estimate counts as degraded.
/// In a 3-voxel band, voxels beyond 1.27 voxels of the surface lack a full 3x3x3 stencil, so a
/// footpoint often has one or two such corners; renormalising over the others keeps the measured
/// curvature error below 0.3% on the test shapes, so only larger losses are flagged.
constexpr double kDegradedWeight = 0.5;
constexpr int kPad = 1;              // margin of the gathered block
constexpr int kSpan = 8 + 2 * kPad;  // 10

/// Pass-1 results of one record (index units: d in voxels).
struct StencilData {
  std::array<float, 3> gradient{};
  std::array<float, 6> hessian{};  // xx, yy, zz, xy, xz, yz
  float distance = 0.0f;
  bool hasHessian = false;
};

/// Values and active flags of a leaf and a 1-voxel margin, x-major with z contiguous.
struct Block {
  std::array<float, kSpan * kSpan * kSpan> values{};
  std::array<std::uint8_t, kSpan * kSpan * kSpan> active{};

  static int index(int x, int y, int z) {
    return ((x + kPad) * kSpan + (y + kPad)) * kSpan + (z + kPad);
  }

  template <typename AccessorT>
  void gather(AccessorT& accessor, const openvdb::Coord& origin) {
    for (int ox = -1; ox <= 1; ++ox) {
      const int x0 = std::max(-kPad, ox * 8), x1 = std::min(7 + kPad, ox * 8 + 7);
      for (int oy = -1; oy <= 1; ++oy) {
        const int y0 = std::max(-kPad, oy * 8), y1 = std::min(7 + kPad, oy * 8 + 7);
        for (int oz = -1; oz <= 1; ++oz) {
          const int z0 = std::max(-kPad, oz * 8), z1 = std::min(7 + kPad, oz * 8 + 7);
          const openvdb::Coord neighbor = origin + openvdb::Coord(ox * 8, oy * 8, oz * 8);
          if (const LeafT* leaf = accessor.probeConstLeaf(neighbor)) {
            const float* data = leaf->buffer().data();
            const auto& mask = leaf->getValueMask();
            for (int x = x0; x <= x1; ++x) {
              for (int y = y0; y <= y1; ++y) {
                for (int z = z0; z <= z1; ++z) {
                  const int offset = ((x - ox * 8) << 6) | ((y - oy * 8) << 3) | (z - oz * 8);
                  values[index(x, y, z)] = data[offset];
                  active[index(x, y, z)] = mask.isOn(offset) ? 1 : 0;
                }
              }
            }
          } else {
            const float fill = accessor.getValue(neighbor);
            for (int x = x0; x <= x1; ++x) {
              for (int y = y0; y <= y1; ++y) {
                for (int z = z0; z <= z1; ++z) {
                  values[index(x, y, z)] = fill;
                  active[index(x, y, z)] = 0;
                }
              }
            }
          }
        }
      }
    }
  }
};

/// Pass 1 for one voxel at local (x, y, z) of a gathered block; `scale` converts values to voxels.
StencilData fitStencil(const Block& block, int x, int y, int z, double scale) {
  StencilData result;
  const double center = block.values[Block::index(x, y, z)] * scale;
  result.distance = static_cast<float>(center);
  bool full = true;
  for (int dx = -1; dx <= 1 && full; ++dx) {
    for (int dy = -1; dy <= 1 && full; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        if (!block.active[Block::index(x + dx, y + dy, z + dz)]) {
          full = false;
          break;
        }
      }
    }
  }
  if (full && std::abs(center) <= kNearSurface) {
    double gx = 0, gy = 0, gz = 0, sxx = 0, syy = 0, szz = 0, hxy = 0, hxz = 0, hyz = 0;
    double sumX0 = 0, sumY0 = 0, sumZ0 = 0, total = 0;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const double f = block.values[Block::index(x + dx, y + dy, z + dz)] * scale;
          total += f;
          gx += dx * f;
          gy += dy * f;
          gz += dz * f;
          if (dx == 0) sumX0 += f;
          if (dy == 0) sumY0 += f;
          if (dz == 0) sumZ0 += f;
          hxy += dx * dy * f;
          hxz += dx * dz * f;
          hyz += dy * dz * f;
        }
      }
    }
    // sum over x = +-1 is total - sumX0.
    sxx = ((total - sumX0) - 2.0 * sumX0) / 9.0;
    syy = ((total - sumY0) - 2.0 * sumY0) / 9.0;
    szz = ((total - sumZ0) - 2.0 * sumZ0) / 9.0;
    result.gradient = {static_cast<float>(gx / 18.0), static_cast<float>(gy / 18.0),
                       static_cast<float>(gz / 18.0)};
    result.hessian = {static_cast<float>(sxx),        static_cast<float>(syy),
                      static_cast<float>(szz),        static_cast<float>(hxy / 12.0),
                      static_cast<float>(hxz / 12.0), static_cast<float>(hyz / 12.0)};
    result.hasHessian = true;
    return result;
  }
  // Central or one-sided differences where the neighbours allow.
  for (int axis = 0; axis < 3; ++axis) {
    const int ax = axis == 0, ay = axis == 1, az = axis == 2;
    const int plus = Block::index(x + ax, y + ay, z + az);
    const int minus = Block::index(x - ax, y - ay, z - az);
    double derivative = 0.0;
    if (block.active[plus] && block.active[minus]) {
      derivative = 0.5 * (block.values[plus] - block.values[minus]) * scale;
    } else if (block.active[plus]) {
      derivative = block.values[plus] * scale - center;
    } else if (block.active[minus]) {
      derivative = center - block.values[minus] * scale;
    }
    result.gradient[axis] = static_cast<float>(derivative);
  }
  return result;
}

/// Trilinear interpolation of pass-1 data at an index-space point, over the corners that have a
/// Hessian. Looks voxels up through the 27 leaves around the current one (setLeaf), where every
/// footpoint of a 3-voxel band lies, and through the band's hash elsewhere; keeps the gathered
/// corners of recent cells (3 in 4 interpolations on the bunny reuse them).
class Interpolator {
 public:
  Interpolator(const LeafTable& band, const std::vector<StencilData>& stencils)
      : band_(band), stencils_(stencils) {}

  /// Makes the leaf with origin `origin` (and its 26 neighbours) the current one.
  void setLeaf(const openvdb::Coord& origin) {
    origin_ = origin;
    for (int slot = 0; slot < 27; ++slot) {
      const openvdb::Coord neighbor =
          origin + openvdb::Coord((slot / 9 - 1) * 8, ((slot / 3) % 3 - 1) * 8, (slot % 3 - 1) * 8);
      neighbors_[static_cast<std::size_t>(slot)] = band_.findLeaf(neighbor);
    }
    hasLeaf_ = true;
  }

  struct Result {
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
    double distance = 0.0;
    double weight = 0.0;  ///< trilinear weight of the corners that contributed (1 = all)
  };

  /// The interpolated data at `point` (index space); weight 0 when no corner has a Hessian.
  Result at(const Eigen::Vector3d& point) {
    const Eigen::Vector3d base = point.array().floor();
    const Eigen::Vector3d t = point - base;
    const openvdb::Coord corner0(static_cast<int>(base.x()), static_cast<int>(base.y()),
                                 static_cast<int>(base.z()));
    const CellCorners& cell = cornersOf(corner0);
    std::array<double, 11> sum{};
    for (int corner = 0; corner < 8; ++corner) {
      if (((cell.usable >> corner) & 1u) == 0) continue;
      const int cx = corner & 1, cy = (corner >> 1) & 1, cz = (corner >> 2) & 1;
      const double w =
          (cx ? t.x() : 1.0 - t.x()) * (cy ? t.y() : 1.0 - t.y()) * (cz ? t.z() : 1.0 - t.z());
      if (w <= 0.0) continue;
      const std::array<float, 10>& data = cell.data[static_cast<std::size_t>(corner)];
      sum[0] += w;
      for (int k = 0; k < 10; ++k) sum[1 + k] += w * data[static_cast<std::size_t>(k)];
    }
    Result result;
    result.weight = sum[0];
    const double scale = sum[0] > 0.0 ? 1.0 / sum[0] : 0.0;
    result.distance = sum[1] * scale;
    result.gradient = Eigen::Vector3d(sum[2], sum[3], sum[4]) * scale;
    result.hessian << sum[5], sum[8], sum[9],  //
        sum[8], sum[6], sum[10],               //
        sum[9], sum[10], sum[7];
    result.hessian *= scale;
    return result;
  }

 private:
  /// The pass-1 data of a cell's eight corners (distance, gradient, Hessian), gathered once: the
  /// footpoints of the voxels along one normal line share a cell.
  struct CellCorners {
    openvdb::Coord cell{std::numeric_limits<int>::min()};
    std::uint8_t usable = 0;  ///< bit c: corner c is active and has a Hessian
    std::array<std::array<float, 10>, 8> data{};
  };

  /// The cached corners of the cell at `corner0` (direct-mapped on the low three bits of each
  /// coordinate, so the cells of one 8^3 window never evict each other).
  const CellCorners& cornersOf(const openvdb::Coord& corner0) {
    CellCorners& cell = cells_[static_cast<std::size_t>(
        ((corner0.x() & 7) << 6) | ((corner0.y() & 7) << 3) | (corner0.z() & 7))];
    if (cell.cell == corner0) return cell;
    cell.cell = corner0;
    cell.usable = 0;
    for (int corner = 0; corner < 8; ++corner) {
      const std::int64_t record =
          find(corner0 + openvdb::Coord(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1));
      if (record < 0) continue;
      const StencilData& source = stencils_[static_cast<std::size_t>(record)];
      if (!source.hasHessian) continue;
      cell.usable = static_cast<std::uint8_t>(cell.usable | (1u << corner));
      auto& data = cell.data[static_cast<std::size_t>(corner)];
      data[0] = source.distance;
      for (int k = 0; k < 3; ++k) data[1 + k] = source.gradient[k];
      for (int k = 0; k < 6; ++k) data[4 + k] = source.hessian[k];
    }
    return cell;
  }

  std::vector<CellCorners> cells_ = std::vector<CellCorners>(512);

  /// Record index of voxel `ijk`, or -1 when it is not in the band.
  std::int64_t find(const openvdb::Coord& ijk) {
    if (hasLeaf_) {
      // Leaf steps -1, 0, 1 along each axis (arithmetic shift = floor division by 8).
      const int sx = (ijk.x() - origin_.x()) >> 3, sy = (ijk.y() - origin_.y()) >> 3,
                sz = (ijk.z() - origin_.z()) >> 3;
      if (sx >= -1 && sx <= 1 && sy >= -1 && sy <= 1 && sz >= -1 && sz <= 1) {
        const std::int64_t leaf =
            neighbors_[static_cast<std::size_t>((sx + 1) * 9 + (sy + 1) * 3 + (sz + 1))];
        if (leaf < 0) return -1;
        return LeafTable::recordIndex(band_.entries()[static_cast<std::size_t>(leaf)], ijk);
      }
    }
    return bandCursor_.record(ijk);
  }

  const LeafTable& band_;
  const std::vector<StencilData>& stencils_;
  LeafCursor bandCursor_{band_};
  bool hasLeaf_ = false;
  openvdb::Coord origin_;
  std::array<std::int64_t, 27> neighbors_{};
};

/// Eigen-decomposition of the Hessian restricted to the plane orthogonal to `normal`:
/// curvatures k1 >= k2 (1/voxel) and the unit direction of k1, in closed form: in the basis
/// (b0, b1) = tangentBasis(normal) the restriction is [[a, b], [b, c]], and e1 is the direction
/// at angle atan2(2b, a - c) / 2 from b0 (the one with a non-negative b0 component; b0 at an
/// umbilic), found without trigonometry.
void principalCurvatures(const Eigen::Matrix3d& hessian, const Eigen::Vector3d& normal, double& k1,
                         double& k2, Eigen::Vector3d& e1) {
  const auto basis = tangentBasis(normal);
  const Eigen::Vector3d hb0 = hessian * basis[0];
  const double a = basis[0].dot(hb0);
  const double b = basis[1].dot(hb0);
  const double c = basis[1].dot(hessian * basis[1]);
  const double half = 0.5 * (a - c);
  const double radius = std::sqrt(half * half + b * b);
  k1 = 0.5 * (a + c) + radius;
  k2 = 0.5 * (a + c) - radius;
  // An eigenvector of k1: (half + radius, b) when a >= c, else (b, radius - half); both are long
  // (|v| >= radius) where they are used.
  double u = half >= 0.0 ? half + radius : b;
  double v = half >= 0.0 ? b : radius - half;
  const double length = std::sqrt(u * u + v * v);
  if (!(length > 1e-300)) {
    e1 = basis[0];
    return;
  }
  if (u < 0.0) {
    u = -u;
    v = -v;
  }
  e1 = (u / length) * basis[0] + (v / length) * basis[1];
}

}  // namespace

std::vector<detail::BandRecord> referenceSurfaceRecords(const detail::BandLayout& layout,
                                                        const detail::RecordCodec& codec) {
  const double voxelSize = layout.frame().voxelSize();
  const double scale = 1.0 / voxelSize;  // world distance -> voxels
  const LeafTable& band = layout.table();
  const auto& entries = band.entries();
  std::vector<StencilData> stencils(band.voxelCount());
  std::vector<BandRecord> records(band.voxelCount());

  // Pass 1: quadric fits and gradients.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, entries.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      auto accessor = layout.grid()->getConstAccessor();
                      Block block;
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        const LeafEntry& entry = entries[i];
                        block.gather(accessor, entry.origin);
                        std::uint32_t record = entry.base;
                        entry.forEachOn([&](int offset) {
                          stencils[record++] =
                              fitStencil(block, offset >> 6, (offset >> 3) & 7, offset & 7, scale);
                        });
                      }
                    });

  // Pass 2: footpoints, normals, curvatures.
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, entries.size(), 16),
      [&](const tbb::blocked_range<std::size_t>& range) {
        Interpolator interpolator(band, stencils);
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const LeafEntry& entry = entries[i];
          interpolator.setLeaf(entry.origin);
          std::uint32_t record = entry.base;
          entry.forEachOn([&](int offset) {
            const Eigen::Vector3d p(entry.origin.x() + (offset >> 6),
                                    entry.origin.y() + ((offset >> 3) & 7),
                                    entry.origin.z() + (offset & 7));
            const StencilData& own = stencils[record];
            const double d = own.distance;
            Eigen::Vector3d gradient(own.gradient[0], own.gradient[1], own.gradient[2]);
            const double gradientLength = gradient.norm();
            Approximant a;  // index frame, world distance and curvatures
            a.kind = TargetKind::Surface;
            Eigen::Vector3d normal = gradientLength > 1e-12
                                         ? Eigen::Vector3d(gradient / gradientLength)
                                         : Eigen::Vector3d::UnitZ();
            bool ok =
                !(own.hasHessian && gradientLength < kMinimumGradient) && gradientLength > 1e-12;
            Eigen::Vector3d footpoint = p - d * normal;
            double distance = d;
            Interpolator::Result at;
            bool degraded = false, converged = false;
            for (int round = 0; round < 3 && ok; ++round) {
              at = interpolator.at(footpoint);
              const double length = at.gradient.norm();
              if (at.weight < 0.25 || length < 1e-6) {
                ok = false;
                break;
              }
              degraded = degraded || at.weight < kDegradedWeight;
              normal = at.gradient / length;
              // Project onto the zero level along the normal, then re-aim through p.
              const Eigen::Vector3d onSurface = footpoint - (at.distance / length) * normal;
              distance = (p - onSurface).dot(normal);
              const Eigen::Vector3d previous = footpoint;
              footpoint = p - distance * normal;
              // Converged: the normal and Hessian interpolated at the previous iterate, at most
              // kFootpointStep away, stand for the footpoint's.
              if ((footpoint - previous).squaredNorm() < kFootpointStep * kFootpointStep) {
                converged = true;
                break;
              }
            }
            if (ok && !converged) {
              at = interpolator.at(footpoint);
              if (at.weight < 0.25 || std::abs(at.distance) > 0.5) ok = false;
              degraded = degraded || at.weight < kDegradedWeight;
            }
            double k1 = 0.0, k2 = 0.0;
            Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();  // set below on every path
            if (ok) {
              principalCurvatures(at.hessian, normal, k1, k2, e1);
              if (1.0 + distance * k1 < kMinimumFocal || 1.0 + distance * k2 < kMinimumFocal) {
                ok = false;
              }
            }
            if (ok) {
              if (std::abs(k1) > 1.0 || std::abs(k2) > 1.0) {
                a.flags |= kFlagCurvatureClamped;
                k1 = std::clamp(k1, -1.0, 1.0);
                k2 = std::clamp(k2, -1.0, 1.0);
              }
              if (degraded) a.flags |= kFlagDegradedEstimate;
            } else {
              // Cut locus or unresolved: the local gradient, no curvature.
              a.flags |= kFlagCutLocus;
              normal = gradientLength > 1e-12 ? Eigen::Vector3d(gradient / gradientLength)
                                              : Eigen::Vector3d::UnitZ();
              distance = d;
              k1 = k2 = 0.0;
              e1 = tangentBasis(normal)[0];
            }
            a.distance = distance * voxelSize;
            a.normal = normal;
            a.tangent = e1;
            a.k1 = k1 * scale;
            a.k2 = k2 * scale;
            records[record] = codec.encode(a);
            ++record;
          });
        }
      });
  return records;
}

}  // namespace d2vdb::test
