// Marching squares on an axis-aligned plane through a sparse grid (IsoLines.h).
#include "d2vdb/contour/IsoLines.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>

#include "d2vdb/contour/IsoSurface.h"
#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

constexpr int kSliceBlockSize = 8;

void checkAxisAligned(const openvdb::math::Transform& transform) {
  if (!transform.isLinear()) {
    throw InputError("slices need a grid with a linear transform; this one is " +
                     transform.mapType());
  }
  for (int axis = 0; axis < 3; ++axis) {
    openvdb::Vec3d unit(0.0);
    unit[axis] = 1.0;
    const openvdb::Vec3d column = transform.baseMap()->applyJacobian(unit);
    for (int other = 0; other < 3; ++other) {
      if (other != axis && std::abs(column[other]) > 1e-9 * std::abs(column[axis])) {
        throw InputError(
            "slices need an axis-aligned grid transform (scale and translation "
            "only); this one rotates or shears the index axes");
      }
    }
  }
}

/// Marching squares over the plane, collecting vertices and oriented segments.
template <typename GridT>
class SquareMarcher {
  using ValueT = typename GridT::ValueType;

 public:
  SquareMarcher(const GridT& grid, const SliceOptions& options)
      : grid_(grid), options_(options), accessor_(grid.getConstAccessor()) {
    axis_ = options.axis;
    u_ = (axis_ + 1) % 3;
    v_ = (axis_ + 2) % 3;
    openvdb::Vec3d onPlane(0.0);
    onPlane[axis_] = options.offset;
    planeIndex_ = grid.transform().worldToIndex(onPlane)[axis_];
    const double layer = std::floor(planeIndex_);
    if (!(std::abs(layer) < 1e9)) {
      throw InputError("the slice plane at " + std::to_string(options.offset) +
                       " lies outside the grid's index range");
    }
    layer_ = static_cast<int>(layer);
    blend_ = planeIndex_ - layer;
  }

  Slice run() {
    std::vector<std::pair<int, int>> blocks;
    for (auto leaf = grid_.tree().cbeginLeaf(); leaf; ++leaf) {
      const openvdb::Coord origin = leaf->origin();
      const bool holdsLayer = origin[axis_] <= layer_ && layer_ < origin[axis_] + kSliceBlockSize;
      const bool holdsNext = blend_ > 0.0 && origin[axis_] <= layer_ + 1 &&
                             layer_ + 1 < origin[axis_] + kSliceBlockSize;
      if (!holdsLayer && !holdsNext) continue;
      for (int du = 0; du <= kSliceBlockSize; du += kSliceBlockSize) {
        for (int dv = 0; dv <= kSliceBlockSize; dv += kSliceBlockSize) {
          blocks.emplace_back(origin[u_] - du, origin[v_] - dv);
        }
      }
    }
    std::sort(blocks.begin(), blocks.end());
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    for (const auto& [bu, bv] : blocks) marchBlock(bu, bv);
    return chain();
  }

 private:
  double planeValue(int i, int j) {
    openvdb::Coord ijk;
    ijk[axis_] = layer_;
    ijk[u_] = i;
    ijk[v_] = j;
    const double first = static_cast<double>(accessor_.getValue(ijk));
    if (blend_ == 0.0) return first;
    ijk[axis_] = layer_ + 1;
    return first + blend_ * (static_cast<double>(accessor_.getValue(ijk)) - first);
  }

  /// Vertex on the edge from grid point (i, j) along plane axis `direction` (0 = u, 1 = v).
  std::uint32_t vertex(int i, int j, int direction, double start, double end) {
    const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 33) ^
                              (static_cast<std::uint64_t>(static_cast<std::uint32_t>(j)) << 1) ^
                              static_cast<std::uint64_t>(direction);
    const auto [found, inserted] = vertexOfEdge_.try_emplace(key, 0u);
    if (!inserted) return found->second;
    const double t = std::clamp((options_.isoValue - start) / (end - start), kCornerClearance,
                                1.0 - kCornerClearance);
    openvdb::Vec3d index;
    index[axis_] = planeIndex_;
    index[u_] = i + (direction == 0 ? t : 0.0);
    index[v_] = j + (direction == 1 ? t : 0.0);
    const openvdb::Vec3d world = grid_.transform().indexToWorld(index);
    found->second = static_cast<std::uint32_t>(points_.size());
    points_.emplace_back(world[u_], world[v_]);
    next_.push_back(-1);
    incoming_.push_back(false);
    return found->second;
  }

  void marchBlock(int bu, int bv) {
    std::array<std::array<double, kSliceBlockSize + 1>, kSliceBlockSize + 1> values{};
    for (int i = 0; i <= kSliceBlockSize; ++i) {
      for (int j = 0; j <= kSliceBlockSize; ++j) values[i][j] = planeValue(bu + i, bv + j);
    }
    const double iso = options_.isoValue;
    // Corners q0..q3 counter-clockwise; edge e joins q_e and q_(e+1).
    static constexpr std::array<std::array<int, 2>, 4> kCorner{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    for (int i = 0; i < kSliceBlockSize; ++i) {
      for (int j = 0; j < kSliceBlockSize; ++j) {
        std::array<double, 4> value{};
        std::array<bool, 4> inside{};
        for (int q = 0; q < 4; ++q) {
          value[q] = values[i + kCorner[q][0]][j + kCorner[q][1]];
          inside[q] = value[q] < iso;
        }
        std::array<int, 4> crossedEdges{};
        int crossed = 0;
        for (int e = 0; e < 4; ++e) {
          if (inside[e] != inside[(e + 1) % 4]) crossedEdges[crossed++] = e;
        }
        if (crossed == 0) continue;
        std::array<std::pair<int, int>, 2> segments{};
        int segmentCount = 0;
        if (crossed == 2) {
          segments[segmentCount++] = {crossedEdges[0], crossedEdges[1]};
        } else {
          const double diagonal02 = (value[0] - iso) * (value[2] - iso);
          const double diagonal13 = (value[1] - iso) * (value[3] - iso);
          const bool joined = inside[0] ? diagonal02 > diagonal13 : diagonal13 > diagonal02;
          for (int q = 0; q < 4; ++q) {
            if (inside[q] != joined) segments[segmentCount++] = {(q + 3) % 4, q};
          }
        }
        // Twice the midpoint of edge e, coordinate c (integers, so the test below is exact).
        const auto midpoint2 = [](int e, int c) { return kCorner[e][c] + kCorner[(e + 1) % 4][c]; };
        for (int s = 0; s < segmentCount; ++s) {
          auto [from, to] = segments[s];
          // Is corner q_from left of the segment from edge `from` to edge `to`?
          const int du = midpoint2(to, 0) - midpoint2(from, 0);
          const int dv = midpoint2(to, 1) - midpoint2(from, 1);
          const int pu = 2 * kCorner[from][0] - midpoint2(from, 0);
          const int pv = 2 * kCorner[from][1] - midpoint2(from, 1);
          const bool left = du * pv - dv * pu > 0;
          if (left != inside[from]) std::swap(from, to);
          const std::uint32_t a = edgeVertex(bu + i, bv + j, from, value);
          const std::uint32_t b = edgeVertex(bu + i, bv + j, to, value);
          next_[a] = static_cast<std::int64_t>(b);
          incoming_[b] = true;
        }
      }
    }
  }

  /// The vertex of cell edge e (0: bottom, 1: right, 2: top, 3: left) of cell (i, j).
  std::uint32_t edgeVertex(int i, int j, int e, const std::array<double, 4>& value) {
    switch (e) {
      case 0:
        return vertex(i, j, 0, value[0], value[1]);
      case 1:
        return vertex(i + 1, j, 1, value[1], value[2]);
      case 2:
        return vertex(i, j + 1, 0, value[3], value[2]);
      default:
        return vertex(i, j, 1, value[0], value[3]);
    }
  }

  Slice chain() {
    Slice slice;
    slice.axis = axis_;
    slice.offset = options_.offset;
    slice.planeAxes = {u_, v_};
    std::vector<bool> used(points_.size(), false);
    const auto follow = [&](std::size_t start, bool closed) {
      IsoLine line;
      line.closed = closed;
      std::int64_t current = static_cast<std::int64_t>(start);
      while (current >= 0 && !used[current]) {
        used[current] = true;
        line.points.push_back(points_[current]);
        current = next_[current];
      }
      slice.lines.push_back(std::move(line));
    };
    for (std::size_t v = 0; v < points_.size(); ++v) {
      if (!used[v] && !incoming_[v]) follow(v, false);
    }
    for (std::size_t v = 0; v < points_.size(); ++v) {
      if (!used[v]) follow(v, true);
    }
    return slice;
  }

  const GridT& grid_;
  const SliceOptions& options_;
  typename GridT::ConstAccessor accessor_;
  int axis_ = 2, u_ = 0, v_ = 1, layer_ = 0;
  double planeIndex_ = 0.0, blend_ = 0.0;
  std::unordered_map<std::uint64_t, std::uint32_t> vertexOfEdge_;
  std::vector<Eigen::Vector2d> points_;
  std::vector<std::int64_t> next_;
  std::vector<bool> incoming_;
};

template <typename GridT>
Slice sliceGrid(const GridT& grid, const SliceOptions& options) {
  if (options.axis < 0 || options.axis > 2) {
    throw InputError("the slice axis must be x, y or z (0, 1 or 2)");
  }
  if (!std::isfinite(options.offset) || !std::isfinite(options.isoValue)) {
    throw InputError("the slice offset and iso-value must be finite numbers");
  }
  checkAxisAligned(grid.transform());
  return SquareMarcher<GridT>(grid, options).run();
}

}  // namespace

Slice sliceIsoLines(const openvdb::FloatGrid& grid, const SliceOptions& options) {
  return sliceGrid(grid, options);
}

Slice sliceIsoLines(const openvdb::DoubleGrid& grid, const SliceOptions& options) {
  return sliceGrid(grid, options);
}

Slice sliceIsoLines(const openvdb::GridBase& grid, const SliceOptions& options) {
  if (const auto* floatGrid = dynamic_cast<const openvdb::FloatGrid*>(&grid)) {
    return sliceIsoLines(*floatGrid, options);
  }
  if (const auto* doubleGrid = dynamic_cast<const openvdb::DoubleGrid*>(&grid)) {
    return sliceIsoLines(*doubleGrid, options);
  }
  throw InputError("grid '" + grid.getName() + "' holds " + grid.valueType() +
                   " values; slices need a float or double grid");
}

}  // namespace d2vdb
