// The 16-byte record of a band voxel and the encodings it uses (octahedral unit vectors, 16-bit
// "diamond" angles, half floats), and the codec between records and Approximants.
#pragma once

#include <openvdb/openvdb.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/field/detail/IndexFrame.h"
#include "d2vdb/field/detail/LeafTable.h"

namespace d2vdb::detail {

/// The 16-byte record of one band voxel (level 0). Vectors are in the field's index frame.
/// - normal: octahedral encoding of the unit normal (surface) or of the direction from the
///   footpoint toward the voxel (curves, points), two snorm16 values;
/// - angle: e1 (surface) or the unit tangent (curve) as an angle about the normal from
///   tangentBasis(normal) (encodeAngle());
/// - c0, c1: surface: k1 h, k2 h as half floats (h = voxel size); curve: kappa h as a half float
///   and the principal normal's angle about the tangent (from tangentBasis(tangent)).
struct BandRecord {
  float distance = 0.0f;  ///< world units (signed for surfaces)
  std::array<std::int16_t, 2> normal{};
  std::uint16_t angle = 0;
  std::uint16_t flags = 0;
  std::uint16_t c0 = 0;
  std::uint16_t c1 = 0;
};
static_assert(sizeof(BandRecord) == 16, "band records are 16 bytes");

/// The fold of the octahedral map between the lower hemisphere and the corners of the square
/// |x| + |y| <= 1: (x, y) becomes ((1 - |y|) sign x, (1 - |x|) sign y), with sign 0 = +1.
/// Encoding applies it to the projection of a direction with z < 0, decoding to a code outside the
/// diamond |x| + |y| <= 1. Inline: the field builder encodes every band voxel's normal.
inline void foldOctahedral(double& x, double& y) {
  const double foldedX = (1.0 - std::abs(y)) * (x >= 0.0 ? 1.0 : -1.0);
  const double foldedY = (1.0 - std::abs(x)) * (y >= 0.0 ? 1.0 : -1.0);
  x = foldedX;
  y = foldedY;
}

/// `value` clamped to [-1, 1] as a signed normalized 16-bit integer (value x 32767, rounded to
/// nearest, ties up).
inline std::int16_t quantizeSnorm16(double value) {
  return static_cast<std::int16_t>(nearestInt(std::clamp(value, -1.0, 1.0) * 32767.0));
}

/// Octahedral encoding of a unit vector into two snorm16 values, and its inverse (normalised).
std::array<std::int16_t, 2> encodeOctahedral(const Eigen::Vector3d& unit);
Eigen::Vector3d decodeOctahedral(const std::array<std::int16_t, 2>& code);

/// A deterministic orthonormal pair (b1, b2) with b1 x b2 = unit, for angle encodings.
std::array<Eigen::Vector3d, 2> tangentBasis(const Eigen::Vector3d& unit);
/// The direction of `direction` (orthogonal to `axis`, any non-zero length; zero gives code 0)
/// about `axis`, in the plane of tangentBasis(axis) = (b1, b2), as a 16-bit "diamond angle": with
/// u, v its b1, b2 components, the point (u, v) / (|u| + |v|) on the square |u| + |v| = 1, measured
/// counter-clockwise from b1 along the square's edges, one unit per quadrant, in 1/16384 units.
/// Monotonic in the true angle, with steps of 0.004-0.007 degrees, and free of trigonometry both
/// ways; decodeAngle(encodeAngle(d)) re-encodes to the same code.
std::uint16_t encodeAngle(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction);
/// The unit vector with diamond-angle code `code` about `axis` (encodeAngle()).
Eigen::Vector3d decodeAngle(const Eigen::Vector3d& axis, std::uint16_t code);

/// IEEE half-float bits of a value (OpenVDB's half), and back.
std::uint16_t encodeHalf(double value);
double decodeHalf(std::uint16_t bits);

/// Converts between BandRecords and Approximants for one field (its kind and index frame).
/// Decoding is exact (same record, same answer) and encode(decode(r)) gives r back, so records
/// survive any number of conversions.
class RecordCodec {
 public:
  RecordCodec(TargetKind kind, const IndexFrame& frame) : kind_(kind), frame_(frame) {}

  TargetKind kind() const { return kind_; }
  const IndexFrame& frame() const { return frame_; }

  /// Encodes an approximant given in the index frame (directions), distance in world units and
  /// curvatures in 1/world units. Only distance, normal, tangent, k1 (and k2 for surfaces,
  /// principalNormal for curves) and flags are kept; the footpoint is re-derived on decoding as
  /// centre - distance * normal.
  BandRecord encode(const Approximant& indexFrameApproximant) const;
  /// The approximant of `record` stored for voxel `ijk` (world units, world frame, taken at the
  /// voxel centre).
  Approximant decodeBand(const BandRecord& record, const openvdb::Coord& ijk) const;
  /// The coarse approximant at index-space point `center` from a band sample: its record and its
  /// footpoint (index space). Footpoint s, normal (centre - s) / |centre - s| (signed by the
  /// sample's normal for surfaces), the sample's curvatures; flagged kFlagFarField.
  Approximant decodeCoarse(const BandRecord& record, const Eigen::Vector3d& footpoint,
                           const Eigen::Vector3d& center) const;

 private:
  TargetKind kind_;
  IndexFrame frame_;
};

}  // namespace d2vdb::detail
