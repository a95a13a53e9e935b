#include "d2vdb/field/detail/SeedDilation.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "d2vdb/core/Error.h"

namespace d2vdb::detail {

bool SeedDilation::contains(const std::array<int, 3>& w) const {
  int excess = 0;
  for (const int c : w) excess += std::max(std::abs(c) - cubeSteps, 0);
  return excess <= diamondSteps;
}

std::int64_t SeedDilation::offsetCount() const {
  // By the excess e_i = max(|w_i| - cubeSteps, 0) of each coordinate: 2 cubeSteps + 1 values of
  // w_i have e_i = 0, two have each e_i > 0; the offsets are those with e_1 + e_2 + e_3 <=
  // diamondSteps.
  const auto values = [&](int excess) -> std::int64_t {
    return excess == 0 ? 2 * cubeSteps + 1 : 2;
  };
  std::int64_t count = 0;
  for (int e1 = 0; e1 <= diamondSteps; ++e1) {
    for (int e2 = 0; e1 + e2 <= diamondSteps; ++e2) {
      for (int e3 = 0; e1 + e2 + e3 <= diamondSteps; ++e3) {
        count += values(e1) * values(e2) * values(e3);
      }
    }
  }
  return count;
}

bool withinRadiusOfVoxel(const std::array<int, 3>& w, double radius) {
  double squared = 0.0;
  for (const int c : w) {
    const double gap = std::max(std::abs(c) - 0.5, 0.0);
    squared += gap * gap;
  }
  return squared < radius * radius;
}

SeedDilation seedDilation(double radius) {
  if (!(radius > 0.0) || radius > 200.0) {
    throw InputError("seed dilation: the radius must lie in (0, 200] voxels");
  }
  // Offsets within the radius have |w_i| - 1/2 < radius in every coordinate, so the cube of
  // ceil(radius - 1/2) steps contains them all.
  const int cube = std::max(0, static_cast<int>(std::ceil(radius - 0.5)));
  // The offsets that must be covered, by symmetry only those with 0 <= z <= y <= x (the
  // dilations are symmetric under sign changes and permutations of the coordinates too).
  std::vector<std::array<int, 3>> needed;
  for (int x = 0; x <= cube; ++x) {
    for (int y = 0; y <= x; ++y) {
      for (int z = 0; z <= y; ++z) {
        if (withinRadiusOfVoxel({x, y, z}, radius)) needed.push_back({x, y, z});
      }
    }
  }
  SeedDilation best{cube, 0};
  std::int64_t bestCount = best.offsetCount();
  for (int total = 0; total <= cube; ++total) {
    for (int diamond = 0; diamond <= total; ++diamond) {
      const SeedDilation candidate{total - diamond, diamond};
      const bool covers = std::all_of(needed.begin(), needed.end(),
                                      [&](const auto& w) { return candidate.contains(w); });
      if (!covers) continue;
      const std::int64_t count = candidate.offsetCount();
      if (count < bestCount || (count == bestCount && total < best.cubeSteps + best.diamondSteps)) {
        best = candidate;
        bestCount = count;
      }
    }
  }
  return best;
}

}  // namespace d2vdb::detail
