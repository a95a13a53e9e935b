// Surface approximants from a narrow-band level set (SurfaceEstimator.h).
#include "d2vdb/field/detail/SurfaceEstimator.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace d2vdb::detail {
namespace {

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

/// Pass-1 results of one band voxel (index units: d in voxels): the value of the quadric fit and
/// its gradient and Hessian (xx, yy, zz, xy, xz, yz) where the voxel has a fit (its bit in the
/// leaf's FitMask), else the distance and a finite-difference gradient (Hessian unused).
/// Left uninitialised until pass 1 writes it (the Hessian only where the voxel has a fit).
struct StencilData {
  float distance;
  std::array<float, 3> gradient;
  std::array<float, 6> hessian;
};

/// An uninitialised array of `count` trivial values, for scratch data that is written before it is
/// read (no zeroing pass over it).
template <typename T>
class ScratchArray {
  static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>,
                "scratch values are never constructed nor destroyed");

 public:
  explicit ScratchArray(std::size_t count) : data_(new T[std::max<std::size_t>(count, 1)]) {}
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }

 private:
  std::unique_ptr<T[]> data_;
};

/// The voxels of one leaf that have a quadric fit, in LeafEntry::mask order.
using FitMask = std::array<std::uint64_t, 8>;

// ---- Pass 1: quadric fits ----------------------------------------------------------------------

/// Pass 1 for the voxels of one leaf. The leaf and a 1-voxel margin are gathered (values and
/// active bits); the fit's ten moments sum f times {1, x, y, z, x^2, y^2, z^2, xy, xz, yz} over a
/// voxel's 3x3x3 stencil, and each is a product of three 3-tap filters along the axes (S = sum,
/// D = difference, C = centre), so they are computed separably: along z over the whole block,
/// then along y, then along x at the voxels that have a fit.
class LeafFitter {
 public:
  /// Fills `out` (the leaf's records, in mask order) and `fits` for the leaf `entry`; `scale`
  /// converts grid values to voxels.
  template <typename AccessorT>
  void fit(AccessorT& accessor, const LeafEntry& entry, double scale, StencilData* out,
           FitMask& fits) {
    gather(accessor, entry.origin);
    filter(scale);
    // Voxels whose 27-voxel stencil is active: the active rows (bit z + 1 = voxel z), eroded.
    std::array<std::uint16_t, 64> full{};
    for (int x = 0; x < 8; ++x) {
      for (int y = 0; y < 8; ++y) {
        unsigned rows = 0x3FF;
        for (int dx = 0; dx <= 2; ++dx) {
          for (int dy = 0; dy <= 2; ++dy) rows &= active_[x + dx][y + dy];
        }
        full[static_cast<std::size_t>(x * 8 + y)] =
            static_cast<std::uint16_t>(rows & (rows >> 1) & (rows << 1));
      }
    }
    fits = FitMask{};
    int record = 0;
    entry.forEachOn([&](int offset) {
      const int x = offset >> 6, y = (offset >> 3) & 7, z = offset & 7;
      StencilData& result = out[record++];
      const double center = scaled_[x + 1][y + 1][z + 1];
      result.distance = static_cast<float>(center);
      if (((full[static_cast<std::size_t>(x * 8 + y)] >> (z + 1)) & 1u) != 0 &&
          std::abs(center) <= kNearSurface) {
        fitVoxel(x, y, z, result);
        fits[static_cast<std::size_t>(offset >> 6)] |= std::uint64_t{1} << (offset & 63);
      } else {
        differences(x, y, z, scale, result);
      }
    });
  }

 private:
  static constexpr int kSpan = 10;  // the leaf and a 1-voxel margin

  /// Values (unscaled) and active bits of the leaf and its margin: block (bx, by, bz) is voxel
  /// origin + (bx - 1, by - 1, bz - 1). Voxels of absent leaves read 0 and are inactive.
  template <typename AccessorT>
  void gather(AccessorT& accessor, const openvdb::Coord& origin) {
    for (auto& plane : active_) plane.fill(0);
    for (int ox = -1; ox <= 1; ++ox) {
      const int bx0 = ox < 0 ? 0 : (ox == 0 ? 1 : 9), bx1 = ox < 0 ? 0 : (ox == 0 ? 8 : 9);
      for (int oy = -1; oy <= 1; ++oy) {
        const int by0 = oy < 0 ? 0 : (oy == 0 ? 1 : 9), by1 = oy < 0 ? 0 : (oy == 0 ? 8 : 9);
        for (int oz = -1; oz <= 1; ++oz) {
          const int bz0 = oz < 0 ? 0 : (oz == 0 ? 1 : 9), bz1 = oz < 0 ? 0 : (oz == 0 ? 8 : 9);
          const LeafT* leaf =
              accessor.probeConstLeaf(origin + openvdb::Coord(ox * 8, oy * 8, oz * 8));
          for (int bx = bx0; bx <= bx1; ++bx) {
            const int lx = bx - 1 - ox * 8;
            for (int by = by0; by <= by1; ++by) {
              const int ly = by - 1 - oy * 8;
              float* row = values_[bx][by].data();
              if (leaf == nullptr) {
                for (int bz = bz0; bz <= bz1; ++bz) row[bz] = 0.0f;
                continue;
              }
              const float* data = leaf->buffer().data() + ((lx << 6) | (ly << 3));
              for (int bz = bz0; bz <= bz1; ++bz) row[bz] = data[bz - 1 - oz * 8];
              // The row's 8 active bits (z = 0..7) sit in byte ly of mask word lx.
              const unsigned bits =
                  static_cast<unsigned>((leaf->getValueMask().template getWord<std::uint64_t>(
                                             static_cast<openvdb::Index>(lx)) >>
                                         (8 * ly)) &
                                        0xFFu);
              unsigned& rowBits = active_[bx][by];
              if (oz < 0) {
                rowBits |= (bits >> 7) & 1u;  // z = 7 of the leaf below: bz = 0
              } else if (oz == 0) {
                rowBits |= bits << 1;
              } else {
                rowBits |= (bits & 1u) << 9;  // z = 0 of the leaf above: bz = 9
              }
            }
          }
        }
      }
    }
  }

  /// Scaled values and the partial filters along z, then y (see the class comment).
  void filter(double scale) {
    for (int bx = 0; bx < kSpan; ++bx) {
      for (int by = 0; by < kSpan; ++by) {
        for (int bz = 0; bz < kSpan; ++bz) scaled_[bx][by][bz] = values_[bx][by][bz] * scale;
      }
    }
    for (int bx = 0; bx < kSpan; ++bx) {
      for (int by = 0; by < kSpan; ++by) {
        const double* f = scaled_[bx][by].data();
        for (int z = 0; z < 8; ++z) {
          sz_[bx][by][z] = f[z] + f[z + 1] + f[z + 2];
          dz_[bx][by][z] = f[z + 2] - f[z];
        }
      }
    }
    for (int bx = 0; bx < kSpan; ++bx) {
      for (int y = 0; y < 8; ++y) {
        for (int z = 0; z < 8; ++z) {
          ss_[bx][y][z] = sz_[bx][y][z] + sz_[bx][y + 1][z] + sz_[bx][y + 2][z];
          ds_[bx][y][z] = sz_[bx][y + 2][z] - sz_[bx][y][z];
          sd_[bx][y][z] = dz_[bx][y][z] + dz_[bx][y + 1][z] + dz_[bx][y + 2][z];
          dd_[bx][y][z] = dz_[bx][y + 2][z] - dz_[bx][y][z];
          sc_[bx][y][z] =
              scaled_[bx][y][z + 1] + scaled_[bx][y + 1][z + 1] + scaled_[bx][y + 2][z + 1];
        }
      }
    }
  }

  /// The quadric fit at leaf voxel (x, y, z): gradient = sum x f / 18, H_xx = (sum_{x=+-1} f -
  /// 2 sum_{x=0} f) / 9, H_xy = sum x y f / 12 (orthogonal monomials on the symmetric stencil).
  void fitVoxel(int x, int y, int z, StencilData& result) const {
    const auto sumX = [&](const auto& a) { return a[x][y][z] + a[x + 1][y][z] + a[x + 2][y][z]; };
    const auto diffX = [&](const auto& a) { return a[x + 2][y][z] - a[x][y][z]; };
    const double total = sumX(ss_);
    const double sumX0 = ss_[x + 1][y][z];
    const double sumY0 = sz_[x][y + 1][z] + sz_[x + 1][y + 1][z] + sz_[x + 2][y + 1][z];
    const double sumZ0 = sumX(sc_);
    const double gx = diffX(ss_), gy = sumX(ds_), gz = sumX(sd_);
    const double hxy = diffX(ds_), hxz = diffX(sd_), hyz = sumX(dd_);
    // The sum over x = +-1 is total - sumX0.
    const double sxx = ((total - sumX0) - 2.0 * sumX0) / 9.0;
    const double syy = ((total - sumY0) - 2.0 * sumY0) / 9.0;
    const double szz = ((total - sumZ0) - 2.0 * sumZ0) / 9.0;
    result.gradient = {static_cast<float>(gx / 18.0), static_cast<float>(gy / 18.0),
                       static_cast<float>(gz / 18.0)};
    result.hessian = {static_cast<float>(sxx),        static_cast<float>(syy),
                      static_cast<float>(szz),        static_cast<float>(hxy / 12.0),
                      static_cast<float>(hxz / 12.0), static_cast<float>(hyz / 12.0)};
  }

  /// Central or one-sided differences where the neighbours of leaf voxel (x, y, z) allow.
  void differences(int x, int y, int z, double scale, StencilData& result) const {
    const double center = scaled_[x + 1][y + 1][z + 1];
    for (int axis = 0; axis < 3; ++axis) {
      const int ax = axis == 0, ay = axis == 1, az = axis == 2;
      const int px = x + 1 + ax, py = y + 1 + ay, pz = z + 1 + az;
      const int mx = x + 1 - ax, my = y + 1 - ay, mz = z + 1 - az;
      const bool plus = ((active_[px][py] >> pz) & 1u) != 0;
      const bool minus = ((active_[mx][my] >> mz) & 1u) != 0;
      double derivative = 0.0;
      if (plus && minus) {
        derivative = 0.5 * (values_[px][py][pz] - values_[mx][my][mz]) * scale;
      } else if (plus) {
        derivative = scaled_[px][py][pz] - center;
      } else if (minus) {
        derivative = center - scaled_[mx][my][mz];
      }
      result.gradient[static_cast<std::size_t>(axis)] = static_cast<float>(derivative);
    }
  }

  template <typename T, int Y, int Z>
  using Planes = std::array<std::array<std::array<T, Z>, Y>, kSpan>;

  Planes<float, kSpan, kSpan> values_{};
  std::array<std::array<unsigned, kSpan>, kSpan> active_{};  ///< bit bz of row (bx, by)
  Planes<double, kSpan, kSpan> scaled_{};                    ///< values in voxels
  Planes<double, kSpan, 8> sz_{}, dz_{};                     ///< S_z f, D_z f at (bx, by, z)
  Planes<double, 8, 8> ss_{}, ds_{}, sd_{}, dd_{}, sc_{};    ///< S_y S_z f, ... at (bx, y, z)
};

/// Pass-1 data of the leaves, kept for three slabs at a time. A slab is the set of leaves with one
/// origin x; the estimator fits slab s + 1 before it finds the footpoints of slab s, whose cells
/// lie in slabs s - 1 to s + 1 (the footpoints of a narrow band are within a voxel or two of their
/// voxels), so three slots of a ring hold all it reads, and they stay in cache instead of a
/// whole band's pass-1 data going through memory.
class FittedSlabs {
 public:
  explicit FittedSlabs(const LeafTable& band)
      : order_(band.entries().size()),
        slabOf_(band.entries().size()),
        localBase_(band.entries().size()),
        fits_(band.entries().size()) {
    const auto& entries = band.entries();
    std::iota(order_.begin(), order_.end(), std::uint32_t{0});
    std::stable_sort(order_.begin(), order_.end(), [&](std::uint32_t a, std::uint32_t b) {
      return entries[a].origin.x() < entries[b].origin.x();
    });
    std::size_t slot = 0;
    for (std::size_t i = 0; i < order_.size(); ++i) {
      const LeafEntry& entry = entries[order_[i]];
      if (i == 0 || entry.origin.x() != entries[order_[i - 1]].origin.x()) {
        starts_.push_back(i);
        slot = 0;
      }
      slabOf_[order_[i]] = static_cast<std::int32_t>(starts_.size() - 1);
      localBase_[order_[i]] = static_cast<std::uint32_t>(slot);
      slot += static_cast<std::size_t>(entry.prefix[7] + countBits(entry.mask[7]));
      slotSize_ = std::max(slotSize_, slot);
    }
    starts_.push_back(order_.size());
    ring_ = std::make_unique<ScratchArray<StencilData>>(kSlots * slotSize_);
  }

  std::size_t slabCount() const { return starts_.size() - 1; }
  /// The leaves (entry indices) of slab `slab`, [begin, end).
  const std::uint32_t* slabBegin(std::size_t slab) const { return order_.data() + starts_[slab]; }
  const std::uint32_t* slabEnd(std::size_t slab) const { return order_.data() + starts_[slab + 1]; }

  /// Whether the pass-1 data of leaf `leaf` is at hand while slab `current` is estimated.
  bool atHand(std::size_t leaf, std::size_t current) const {
    const auto slab = static_cast<std::size_t>(slabOf_[leaf]);
    return slab + 1 >= current && slab <= current + 1;
  }
  /// The leaf's records (mask order) in its slab's slot, and the voxels that have a fit.
  StencilData* data(std::size_t leaf) {
    return ring_->data() + static_cast<std::size_t>(slabOf_[leaf]) % kSlots * slotSize_ +
           localBase_[leaf];
  }
  const StencilData* data(std::size_t leaf) const {
    return const_cast<FittedSlabs*>(this)->data(leaf);
  }
  FitMask& fits(std::size_t leaf) { return fits_[leaf]; }
  const FitMask& fits(std::size_t leaf) const { return fits_[leaf]; }

 private:
  static constexpr std::size_t kSlots = 3;
  std::vector<std::uint32_t> order_;      ///< entry indices by origin x
  std::vector<std::size_t> starts_;       ///< first position in order_ of each slab, and the end
  std::vector<std::int32_t> slabOf_;      ///< slab of each entry
  std::vector<std::uint32_t> localBase_;  ///< first record of each entry within its slot
  std::vector<FitMask> fits_;
  std::size_t slotSize_ = 0;
  std::unique_ptr<ScratchArray<StencilData>> ring_;
};

// ---- Pass 2: footpoints ------------------------------------------------------------------------

/// Two doubles operated on together (SSE2 on x86-64; element by element elsewhere, with the same
/// IEEE operations, so both give the same bits).
struct Pair {
#if defined(__SSE2__)
  __m128d v;
  static Pair load(const double* p) {
    return {_mm_load_pd(p)};
  }
  static Pair broadcast(double a) {
    return {_mm_set1_pd(a)};
  }
  void store(double* p) const {
    _mm_store_pd(p, v);
  }
  friend Pair operator*(Pair a, Pair b) {
    return {_mm_mul_pd(a.v, b.v)};
  }
  friend Pair operator+(Pair a, Pair b) {
    return {_mm_add_pd(a.v, b.v)};
  }
#else
  double v[2];
  static Pair load(const double* p) {
    return {{p[0], p[1]}};
  }
  static Pair broadcast(double a) {
    return {{a, a}};
  }
  void store(double* p) const {
    p[0] = v[0], p[1] = v[1];
  }
  friend Pair operator*(Pair a, Pair b) {
    return {{a.v[0] * b.v[0], a.v[1] * b.v[1]}};
  }
  friend Pair operator+(Pair a, Pair b) {
    return {{a.v[0] + b.v[0], a.v[1] + b.v[1]}};
  }
#endif
};

/// Trilinear interpolation of pass-1 data at an index-space point, over the corners that have a
/// fit. Looks voxels up through the 27 leaves around the current one (setLeaf), where every
/// footpoint of a 3-voxel band lies, and through the band's hash elsewhere; keeps the gathered
/// corners of recent cells (3 in 4 interpolations on the bunny reuse them). The rare footpoint
/// that strays beyond the slabs at hand (FittedSlabs) gets its leaf fitted again here: pass 1 of
/// a leaf depends only on the grid, so this gives the same data.
class Interpolator {
 public:
  Interpolator(const LeafTable& band, const FittedSlabs& slabs, const openvdb::FloatGrid& grid,
               double scale)
      : band_(band), slabs_(slabs), accessor_(grid.getConstAccessor()), scale_(scale) {}

  /// Makes the leaf with origin `origin` (and its 26 neighbours), of slab `slab`, the current one.
  void setLeaf(const openvdb::Coord& origin, std::size_t slab) {
    origin_ = origin;
    slab_ = slab;
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

  /// The interpolated data at `point` (index space, finite); weight 0 when no corner has a fit.
  /// Every corner adds its weight times its data, in corner order; corners without a fit carry
  /// zeros, so they add nothing, exactly as if skipped.
  Result at(const Eigen::Vector3d& point) {
    if (!(point.cwiseAbs().maxCoeff() < kFarPoint)) return {};
    const int ix = floorToInt(point.x()), iy = floorToInt(point.y()), iz = floorToInt(point.z());
    const double tx = point.x() - ix, ty = point.y() - iy, tz = point.z() - iz;
    const CellCorners& cell = cornersOf(openvdb::Coord(ix, iy, iz));
    const double wx[2] = {1.0 - tx, tx}, wy[2] = {1.0 - ty, ty}, wz[2] = {1.0 - tz, tz};
    Pair sum[kLanes / 2];
    for (auto& s : sum) s = Pair::broadcast(0.0);
    for (int corner = 0; corner < 8; ++corner) {
      const Pair w = Pair::broadcast(wx[corner & 1] * wy[(corner >> 1) & 1] * wz[corner >> 2]);
      const double* data = cell.data[static_cast<std::size_t>(corner)].data();
      for (int k = 0; k < kLanes / 2; ++k) sum[k] = sum[k] + w * Pair::load(data + 2 * k);
    }
    alignas(16) std::array<double, kLanes> total;
    for (int k = 0; k < kLanes / 2; ++k) sum[k].store(total.data() + 2 * k);
    Result result;
    result.weight = total[0];
    const double scale = total[0] > 0.0 ? 1.0 / total[0] : 0.0;
    result.distance = total[1] * scale;
    result.gradient = Eigen::Vector3d(total[2], total[3], total[4]) * scale;
    result.hessian << total[5], total[8], total[9],  //
        total[8], total[6], total[10],               //
        total[9], total[10], total[7];
    result.hessian *= scale;
    return result;
  }

 private:
  /// Per corner: 1 (its weight), d, gradient, Hessian (xx, yy, zz, xy, xz, yz), 0; all zero for
  /// a corner without a fit.
  static constexpr int kLanes = 12;

  /// Points farther out than this (index units) lie beyond every band (and int coordinates).
  static constexpr double kFarPoint = 1e9;

  /// floor(value) for |value| < 2^31.
  static int floorToInt(double value) {
    const int truncated = static_cast<int>(value);
    return truncated - (value < static_cast<double>(truncated) ? 1 : 0);
  }

  /// The pass-1 data of a cell's eight corners, gathered once: the footpoints of the voxels along
  /// one normal line share a cell.
  struct CellCorners {
    alignas(16) std::array<std::array<double, kLanes>, 8> data{};
    openvdb::Coord cell{std::numeric_limits<int>::min()};
  };

  /// The cached corners of the cell at `corner0` (direct-mapped on the low three bits of each
  /// coordinate, so the cells of one 8^3 window never evict each other).
  const CellCorners& cornersOf(const openvdb::Coord& corner0) {
    CellCorners& cell = cells_[static_cast<std::size_t>(
        ((corner0.x() & 7) << 6) | ((corner0.y() & 7) << 3) | (corner0.z() & 7))];
    if (cell.cell == corner0) return cell;
    cell.cell = corner0;
    for (int corner = 0; corner < 8; ++corner) {
      auto& data = cell.data[static_cast<std::size_t>(corner)];
      const StencilData* source =
          fitAt(corner0 + openvdb::Coord(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1));
      if (source == nullptr) {
        data.fill(0.0);
        continue;
      }
      data[0] = 1.0;
      data[1] = source->distance;
      for (int k = 0; k < 3; ++k) data[2 + k] = source->gradient[static_cast<std::size_t>(k)];
      for (int k = 0; k < 6; ++k) data[5 + k] = source->hessian[static_cast<std::size_t>(k)];
      data[11] = 0.0;
    }
    return cell;
  }

  /// The pass-1 data of voxel `ijk` if it is in the band and has a fit, else null. The data stay
  /// valid until the next call.
  const StencilData* fitAt(const openvdb::Coord& ijk) {
    std::int64_t leaf = -1;
    // Leaf steps -1, 0, 1 along each axis (arithmetic shift = floor division by 8).
    const int sx = (ijk.x() - origin_.x()) >> 3, sy = (ijk.y() - origin_.y()) >> 3,
              sz = (ijk.z() - origin_.z()) >> 3;
    if (hasLeaf_ && sx >= -1 && sx <= 1 && sy >= -1 && sy <= 1 && sz >= -1 && sz <= 1) {
      leaf = neighbors_[static_cast<std::size_t>((sx + 1) * 9 + (sy + 1) * 3 + (sz + 1))];
    } else {
      leaf = band_.findLeaf(ijk);
    }
    if (leaf < 0) return nullptr;
    const auto index = static_cast<std::size_t>(leaf);
    const LeafEntry& entry = band_.entries()[index];
    const StencilData* data;
    const FitMask* fits;
    if (slabs_.atHand(index, slab_)) {
      data = slabs_.data(index);
      fits = &slabs_.fits(index);
    } else {
      if (!stray_) stray_ = std::make_unique<Stray>();
      if (stray_->leaf != leaf) {
        stray_->fitter.fit(accessor_, entry, scale_, stray_->data.data(), stray_->fits);
        stray_->leaf = leaf;
      }
      data = stray_->data.data();
      fits = &stray_->fits;
    }
    const int offset = ((ijk.x() & 7) << 6) | ((ijk.y() & 7) << 3) | (ijk.z() & 7);
    const int word = offset >> 6;
    const std::uint64_t bit = std::uint64_t{1} << (offset & 63);
    if (((*fits)[static_cast<std::size_t>(word)] & bit) == 0) return nullptr;
    return data + entry.prefix[word] + countBits(entry.mask[word] & (bit - 1));
  }

  /// A leaf beyond the slabs at hand, fitted on demand.
  struct Stray {
    LeafFitter fitter;
    std::array<StencilData, 512> data;
    FitMask fits{};
    std::int64_t leaf = -1;
  };

  std::vector<CellCorners> cells_ = std::vector<CellCorners>(512);
  const LeafTable& band_;
  const FittedSlabs& slabs_;
  openvdb::FloatGrid::ConstAccessor accessor_;
  double scale_;
  std::unique_ptr<Stray> stray_;
  bool hasLeaf_ = false;
  std::size_t slab_ = 0;
  openvdb::Coord origin_;
  std::array<std::int64_t, 27> neighbors_{};
};

// ---- Records -----------------------------------------------------------------------------------
// The functions below compute what RecordCodec::encode and its codecs (RecordCodec.cc) compute for
// a surface, with the same floating-point operations in the same order, so the records are the
// same bits; they only spare the temporaries of the general path.

struct Vec3 {
  double x, y, z;
};
inline double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// a / d and b / d, in one SSE2 division where available (the same IEEE quotients either way).
inline void divide(double a, double b, double d, double& aOverD, double& bOverD) {
#if defined(__SSE2__)
  const __m128d q = _mm_div_pd(_mm_set_pd(b, a), _mm_set1_pd(d));
  aOverD = _mm_cvtsd_f64(q);
  bOverD = _mm_cvtsd_f64(_mm_unpackhi_pd(q, q));
#else
  aOverD = a / d;
  bOverD = b / d;
#endif
}

/// v / length, componentwise.
inline Vec3 divided(const Vec3& v, double length) {
  Vec3 result;
  divide(v.x, v.y, length, result.x, result.y);
  result.z = v.z / length;
  return result;
}

inline Vec3 normalized(const Vec3& v) {
  const double squared = dot(v, v);
  if (!(squared > 0.0)) return v;
  return divided(v, std::sqrt(squared));
}

/// tangentBasis() of RecordCodec.h.
inline void basisOf(const Vec3& unit, Vec3& b1, Vec3& b2) {
  const Vec3 axis = std::abs(unit.x) < 0.6 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 1.0, 0.0};
  b1 = normalized(cross(axis, unit));
  b2 = cross(unit, b1);
}

/// The record of a surface voxel: distance in world units, unit normal and e1 in the index frame,
/// curvatures in 1/world units (as RecordCodec::encode takes them).
BandRecord surfaceRecord(double distance, const Vec3& normal, const Vec3& e1, double k1, double k2,
                         double voxelSize, std::uint16_t flags) {
  BandRecord record;
  record.distance = static_cast<float>(distance);
  record.flags = flags;
  // encodeOctahedral, with both divisions in one instruction
  const double l1 = std::abs(normal.x) + std::abs(normal.y) + std::abs(normal.z);
  double px = 0.0, py = 0.0;
  if (l1 > 0.0) divide(normal.x, normal.y, l1, px, py);
  if (l1 > 0.0 && normal.z < 0.0) foldOctahedral(px, py);
  record.normal = {quantizeSnorm16(px), quantizeSnorm16(py)};
  // decodeOctahedral, likewise
  double qx, qy;
  divide(record.normal[0], record.normal[1], 32767.0, qx, qy);
  const double qz = 1.0 - std::abs(qx) - std::abs(qy);
  if (qz < 0.0) foldOctahedral(qx, qy);
  const Vec3 decoded = normalized({qx, qy, qz});
  // The tangent's component in the decoded normal's plane, and its diamond angle there.
  const double along = dot(e1, decoded);
  Vec3 tangent{e1.x - along * decoded.x, e1.y - along * decoded.y, e1.z - along * decoded.z};
  Vec3 b1, b2;
  basisOf(decoded, b1, b2);
  if (dot(tangent, tangent) < 1e-18) tangent = b1;
  const double u = dot(tangent, b1), v = dot(tangent, b2);
  const double uv = std::abs(u) + std::abs(v);
  if (uv > 0.0) {
    double diamond;  // [0, 4): quadrants 1 to 4 of the (u, v) plane
    if (v >= 0.0) {
      diamond = u >= 0.0 ? v / uv : 1.0 - u / uv;
    } else {
      diamond = u <= 0.0 ? 2.0 - v / uv : 3.0 + u / uv;
    }
    record.angle = static_cast<std::uint16_t>(nearestInt(diamond * 16384.0) & 0xFFFF);
  }
  record.c0 = encodeHalf(k1 * voxelSize);
  record.c1 = encodeHalf(k2 * voxelSize);
  return record;
}

/// Eigen-decomposition of the Hessian restricted to the plane orthogonal to `normal`:
/// curvatures k1 >= k2 (1/voxel) and the unit direction of k1, in closed form: in the basis
/// (b0, b1) = tangentBasis(normal) the restriction is [[a, b], [b, c]], and e1 is the direction
/// at angle atan2(2b, a - c) / 2 from b0 (the one with a non-negative b0 component; b0 at an
/// umbilic), found without trigonometry. `hessian` is row-major.
void principalCurvatures(const std::array<double, 9>& hessian, const Vec3& normal, double& k1,
                         double& k2, Vec3& e1) {
  Vec3 b0, b1;
  basisOf(normal, b0, b1);
  const auto times = [&](const Vec3& v) {
    return Vec3{hessian[0] * v.x + hessian[1] * v.y + hessian[2] * v.z,
                hessian[3] * v.x + hessian[4] * v.y + hessian[5] * v.z,
                hessian[6] * v.x + hessian[7] * v.y + hessian[8] * v.z};
  };
  const Vec3 hb0 = times(b0);
  const double a = dot(b0, hb0);
  const double b = dot(b1, hb0);
  const double c = dot(b1, times(b1));
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
    e1 = b0;
    return;
  }
  if (u < 0.0) {
    u = -u;
    v = -v;
  }
  double cu, cv;
  divide(u, v, length, cu, cv);
  e1 = {cu * b0.x + cv * b1.x, cu * b0.y + cv * b1.y, cu * b0.z + cv * b1.z};
}

/// Pass 2 for the voxels of one leaf, in stages over all of them (own gradient, footpoint rounds,
/// curvatures and records).
class FootpointWork {
 public:
  /// Fills `out` with the records of the leaf `entry`, whose pass-1 data are `stencils` (mask
  /// order) and `ownFits`.
  void estimate(const LeafEntry& entry, const StencilData* stencils, const FitMask& ownFits,
                Interpolator& interpolator, double voxelSize, BandRecord* out) {
    const double scale = 1.0 / voxelSize;
    int count = 0;
    pendingCount_ = 0;
    // Own gradient: the first normal and footpoint.
    entry.forEachOn([&](int offset) {
      const int v = count++;
      const Eigen::Vector3d p(entry.origin.x() + (offset >> 6),
                              entry.origin.y() + ((offset >> 3) & 7),
                              entry.origin.z() + (offset & 7));
      const StencilData& own = stencils[v];
      const bool hasFit =
          ((ownFits[static_cast<std::size_t>(offset >> 6)] >> (offset & 63)) & 1u) != 0;
      const double d = own.distance;
      const Eigen::Vector3d gradient(own.gradient[0], own.gradient[1], own.gradient[2]);
      const double gradientLength = gradient.norm();
      Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
      if (gradientLength > 1e-12) {
        divide(gradient.x(), gradient.y(), gradientLength, normal.x(), normal.y());
        normal.z() = gradient.z() / gradientLength;
      }
      const bool ok = !(hasFit && gradientLength < kMinimumGradient) && gradientLength > 1e-12;
      Voxel& voxel = voxels_[static_cast<std::size_t>(v)];
      voxel.p = p;
      voxel.ownNormal = normal;
      voxel.normal = normal;
      voxel.ownDistance = d;
      voxel.distance = d;
      voxel.footpoint = p - d * normal;
      voxel.ok = ok;
      voxel.converged = false;
      voxel.degraded = false;
      if (ok) pending_[static_cast<std::size_t>(pendingCount_++)] = v;
    });
    // Up to three rounds of interpolation, projection onto the zero level and re-aiming through p.
    for (int round = 0; round < 3 && pendingCount_ > 0; ++round) {
      int next = 0;
      for (int j = 0; j < pendingCount_; ++j) {
        const int v = pending_[static_cast<std::size_t>(j)];
        Voxel& voxel = voxels_[static_cast<std::size_t>(v)];
        voxel.at = interpolator.at(voxel.footpoint);
        const Interpolator::Result& at = voxel.at;
        const double length = at.gradient.norm();
        if (at.weight < 0.25 || !(length >= 1e-6)) {
          voxel.ok = false;
          continue;
        }
        voxel.degraded = voxel.degraded || at.weight < kDegradedWeight;
        double step;  // at.distance / length
        divide(at.gradient.x(), at.gradient.y(), length, voxel.normal.x(), voxel.normal.y());
        divide(at.gradient.z(), at.distance, length, voxel.normal.z(), step);
        // Project onto the zero level along the normal, then re-aim through p.
        const Eigen::Vector3d onSurface = voxel.footpoint - step * voxel.normal;
        voxel.distance = (voxel.p - onSurface).dot(voxel.normal);
        const Eigen::Vector3d previous = voxel.footpoint;
        voxel.footpoint = voxel.p - voxel.distance * voxel.normal;
        // Converged: the normal and Hessian interpolated at the previous iterate, at most
        // kFootpointStep away, stand for the footpoint's.
        if ((voxel.footpoint - previous).squaredNorm() < kFootpointStep * kFootpointStep) {
          voxel.converged = true;
          continue;
        }
        pending_[static_cast<std::size_t>(next++)] = v;
      }
      pendingCount_ = next;
    }
    // Not converged in three rounds: the data at the last footpoint, which must lie near the
    // zero level.
    for (int j = 0; j < pendingCount_; ++j) {
      Voxel& voxel = voxels_[static_cast<std::size_t>(pending_[static_cast<std::size_t>(j)])];
      voxel.at = interpolator.at(voxel.footpoint);
      if (voxel.at.weight < 0.25 || !(std::abs(voxel.at.distance) <= 0.5)) voxel.ok = false;
      voxel.degraded = voxel.degraded || voxel.at.weight < kDegradedWeight;
    }
    // Curvatures and records.
    for (int v = 0; v < count; ++v) {
      const Voxel& voxel = voxels_[static_cast<std::size_t>(v)];
      bool ok = voxel.ok;
      std::uint16_t flags = 0;
      double k1 = 0.0, k2 = 0.0;
      Vec3 e1{1.0, 0.0, 0.0};  // set below on every path
      Vec3 normal{voxel.normal.x(), voxel.normal.y(), voxel.normal.z()};
      double distance = voxel.distance;
      if (ok) {
        const Eigen::Matrix3d& h = voxel.at.hessian;
        principalCurvatures(
            {h(0, 0), h(0, 1), h(0, 2), h(1, 0), h(1, 1), h(1, 2), h(2, 0), h(2, 1), h(2, 2)},
            normal, k1, k2, e1);
        if (1.0 + distance * k1 < kMinimumFocal || 1.0 + distance * k2 < kMinimumFocal) {
          ok = false;
        }
      }
      if (ok) {
        if (std::abs(k1) > 1.0 || std::abs(k2) > 1.0) {
          flags |= kFlagCurvatureClamped;
          k1 = std::clamp(k1, -1.0, 1.0);
          k2 = std::clamp(k2, -1.0, 1.0);
        }
        if (voxel.degraded) flags |= kFlagDegradedEstimate;
      } else {
        // Cut locus or unresolved: the local gradient, no curvature.
        flags |= kFlagCutLocus;
        normal = {voxel.ownNormal.x(), voxel.ownNormal.y(), voxel.ownNormal.z()};
        distance = voxel.ownDistance;
        k1 = k2 = 0.0;
        Vec3 unused;
        basisOf(normal, e1, unused);
      }
      out[v] =
          surfaceRecord(distance * voxelSize, normal, e1, k1 * scale, k2 * scale, voxelSize, flags);
    }
  }

 private:
  /// The state of one voxel's footpoint search (index space, distances in voxels).
  struct Voxel {
    Eigen::Vector3d p, normal, footpoint, ownNormal;
    double distance = 0.0, ownDistance = 0.0;
    Interpolator::Result at;  ///< the data interpolated last
    bool ok = false, converged = false, degraded = false;
  };
  std::array<Voxel, 512> voxels_;
  std::array<int, 512> pending_{};  ///< voxels whose footpoint search goes on
  int pendingCount_ = 0;
};

}  // namespace

std::vector<BandRecord> estimateSurfaceRecords(const BandLayout& layout, const RecordCodec& codec,
                                               const ProgressCallback& progress) {
  const double voxelSize = layout.frame().voxelSize();
  const double scale = 1.0 / voxelSize;  // world distance -> voxels
  const LeafTable& band = layout.table();
  const auto& entries = band.entries();
  const openvdb::FloatGrid& grid = *layout.grid();
  FittedSlabs slabs(band);
  std::vector<BandRecord> records(band.voxelCount());
  (void)codec;

  // Per-thread state, reused from slab to slab (its contents never affect a result).
  struct FitState {
    explicit FitState(const openvdb::FloatGrid& grid) : accessor(grid.getConstAccessor()) {}
    openvdb::FloatGrid::ConstAccessor accessor;
    LeafFitter fitter;
  };
  struct EstimateState {
    EstimateState(const LeafTable& band, const FittedSlabs& slabs, const openvdb::FloatGrid& grid,
                  double scale)
        : interpolator(band, slabs, grid, scale) {}
    Interpolator interpolator;
    FootpointWork work;
  };
  tbb::enumerable_thread_specific<std::unique_ptr<FitState>> fitStates;
  tbb::enumerable_thread_specific<std::unique_ptr<EstimateState>> estimateStates;

  // Pass 1: quadric fits and gradients of one slab.
  const auto fitSlab = [&](std::size_t slab) {
    tbb::parallel_for(
        tbb::blocked_range<const std::uint32_t*>(slabs.slabBegin(slab), slabs.slabEnd(slab), 16),
        [&](const tbb::blocked_range<const std::uint32_t*>& range) {
          auto& state = fitStates.local();
          if (!state) state = std::make_unique<FitState>(grid);
          for (const std::uint32_t leaf : range) {
            state->fitter.fit(state->accessor, entries[leaf], scale, slabs.data(leaf),
                              slabs.fits(leaf));
          }
        });
  };
  // Pass 2: footpoints, normals, curvatures of one slab, leaf by leaf in stages over all of a
  // leaf's voxels.
  const auto estimateSlab = [&](std::size_t slab) {
    tbb::parallel_for(
        tbb::blocked_range<const std::uint32_t*>(slabs.slabBegin(slab), slabs.slabEnd(slab), 16),
        [&](const tbb::blocked_range<const std::uint32_t*>& range) {
          auto& state = estimateStates.local();
          if (!state) state = std::make_unique<EstimateState>(band, slabs, grid, scale);
          for (const std::uint32_t leaf : range) {
            const LeafEntry& entry = entries[leaf];
            state->interpolator.setLeaf(entry.origin, slab);
            state->work.estimate(entry, slabs.data(leaf), slabs.fits(leaf), state->interpolator,
                                 voxelSize, records.data() + entry.base);
          }
        });
  };
  const std::size_t slabCount = slabs.slabCount();
  if (slabCount > 0) fitSlab(0);
  for (std::size_t slab = 0; slab < slabCount; ++slab) {
    if (slab + 1 < slabCount) fitSlab(slab + 1);
    estimateSlab(slab);
    if (progress) progress("field: approximants", static_cast<double>(slab + 1) / slabCount);
  }
  return records;
}

}  // namespace d2vdb::detail
