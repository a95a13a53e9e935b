// Band records and their encodings (RecordCodec.h).
#include "d2vdb/field/detail/RecordCodec.h"

#include <openvdb/math/Half.h>

#include <algorithm>
#include <cmath>

#include "d2vdb/field/detail/LeafTable.h"

namespace d2vdb::detail {
namespace {

/// Codes per quadrant of the diamond angle (encodeAngle()).
constexpr double kAngleSteps = 16384.0;

}  // namespace

// ---- codecs ------------------------------------------------------------------------------------

std::array<std::int16_t, 2> encodeOctahedral(const Eigen::Vector3d& unit) {
  const double l1 = std::abs(unit.x()) + std::abs(unit.y()) + std::abs(unit.z());
  double px = l1 > 0.0 ? unit.x() / l1 : 0.0;
  double py = l1 > 0.0 ? unit.y() / l1 : 0.0;
  if (l1 > 0.0 && unit.z() < 0.0) foldOctahedral(px, py);
  return {quantizeSnorm16(px), quantizeSnorm16(py)};
}

Eigen::Vector3d decodeOctahedral(const std::array<std::int16_t, 2>& code) {
  double px = code[0] / 32767.0, py = code[1] / 32767.0;
  const double z = 1.0 - std::abs(px) - std::abs(py);
  if (z < 0.0) foldOctahedral(px, py);
  return Eigen::Vector3d(px, py, z).normalized();
}

std::array<Eigen::Vector3d, 2> tangentBasis(const Eigen::Vector3d& unit) {
  const Eigen::Vector3d axis =
      std::abs(unit.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d b1 = axis.cross(unit).normalized();
  return {b1, unit.cross(b1)};
}

std::uint16_t encodeAngle(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction) {
  const auto basis = tangentBasis(axis);
  const double u = direction.dot(basis[0]), v = direction.dot(basis[1]);
  const double l1 = std::abs(u) + std::abs(v);
  if (!(l1 > 0.0)) return 0;
  double diamond;  // [0, 4): quadrants 1 to 4 of the (u, v) plane
  if (v >= 0.0) {
    diamond = u >= 0.0 ? v / l1 : 1.0 - u / l1;
  } else {
    diamond = u <= 0.0 ? 2.0 - v / l1 : 3.0 + u / l1;
  }
  return static_cast<std::uint16_t>(nearestInt(diamond * kAngleSteps) & 0xFFFF);
}

Eigen::Vector3d decodeAngle(const Eigen::Vector3d& axis, std::uint16_t code) {
  const auto basis = tangentBasis(axis);
  const double diamond = code / kAngleSteps;
  double u, v;
  if (diamond < 1.0) {
    u = 1.0 - diamond;
    v = diamond;
  } else if (diamond < 2.0) {
    u = 1.0 - diamond;
    v = 2.0 - diamond;
  } else if (diamond < 3.0) {
    u = diamond - 3.0;
    v = 2.0 - diamond;
  } else {
    u = diamond - 3.0;
    v = diamond - 4.0;
  }
  return (u * basis[0] + v * basis[1]).normalized();
}

std::uint16_t encodeHalf(double value) {
  return openvdb::math::half(static_cast<float>(value)).bits();
}

double decodeHalf(std::uint16_t bits) {
  openvdb::math::half value;
  value.setBits(bits);
  return static_cast<double>(static_cast<float>(value));
}

// ---- records -----------------------------------------------------------------------------------

BandRecord RecordCodec::encode(const Approximant& a) const {
  BandRecord record;
  record.distance = static_cast<float>(a.distance);
  record.flags = a.flags;
  record.normal = encodeOctahedral(a.normal);
  const Eigen::Vector3d normal = decodeOctahedral(record.normal);
  if (kind_ == TargetKind::Points) return record;
  Eigen::Vector3d tangent = a.tangent - a.tangent.dot(normal) * normal;
  if (tangent.squaredNorm() < 1e-18) tangent = tangentBasis(normal)[0];
  record.angle = encodeAngle(normal, tangent);  // any length
  if (kind_ == TargetKind::Surface) {
    record.c0 = encodeHalf(a.k1 * frame_.voxelSize());
    record.c1 = encodeHalf(a.k2 * frame_.voxelSize());
  } else {
    record.c0 = encodeHalf(a.k1 * frame_.voxelSize());
    const Eigen::Vector3d decodedTangent = decodeAngle(normal, record.angle);
    Eigen::Vector3d principal =
        a.principalNormal - a.principalNormal.dot(decodedTangent) * decodedTangent;
    if (principal.squaredNorm() < 1e-18) principal = tangentBasis(decodedTangent)[0];
    record.c1 = encodeAngle(decodedTangent, principal);
  }
  return record;
}

Approximant RecordCodec::decodeBand(const BandRecord& record, const openvdb::Coord& ijk) const {
  Approximant a;
  a.kind = kind_;
  a.flags = record.flags;
  a.distance = record.distance;
  const Eigen::Vector3d center(ijk.x(), ijk.y(), ijk.z());
  const Eigen::Vector3d normal = decodeOctahedral(record.normal);
  a.origin = frame_.indexToWorld(center);
  a.footpoint = frame_.indexToWorld(center - (a.distance / frame_.voxelSize()) * normal);
  a.normal = frame_.toWorldDirection(normal);
  if (kind_ == TargetKind::Points) {
    a.tangent = frame_.toWorldDirection(tangentBasis(normal)[0]);
    return a;
  }
  const Eigen::Vector3d tangent = decodeAngle(normal, record.angle);
  a.tangent = frame_.toWorldDirection(tangent);
  if (kind_ == TargetKind::Surface) {
    a.k1 = decodeHalf(record.c0) / frame_.voxelSize();
    a.k2 = decodeHalf(record.c1) / frame_.voxelSize();
  } else {
    a.k1 = decodeHalf(record.c0) / frame_.voxelSize();
    if (a.k1 > 0.0) a.principalNormal = frame_.toWorldDirection(decodeAngle(tangent, record.c1));
  }
  return a;
}

Approximant RecordCodec::decodeCoarse(const BandRecord& record, const Eigen::Vector3d& footpoint,
                                      const Eigen::Vector3d& center) const {
  const Eigen::Vector3d sampleNormal = decodeOctahedral(record.normal);
  Approximant a;
  a.kind = kind_;
  a.flags = static_cast<std::uint16_t>((record.flags & ~kFlagFarField) | kFlagFarField);
  a.origin = frame_.indexToWorld(center);
  a.footpoint = frame_.indexToWorld(footpoint);
  const Eigen::Vector3d offset = center - footpoint;
  const double length = offset.norm();
  double sign = 1.0;
  if (kind_ == TargetKind::Surface && offset.dot(sampleNormal) < 0.0) sign = -1.0;
  const Eigen::Vector3d normal =
      length > 1e-9 ? Eigen::Vector3d(sign * offset / length) : sampleNormal;
  a.distance = sign * length * frame_.voxelSize();
  a.normal = frame_.toWorldDirection(normal);
  const Eigen::Vector3d sampleTangent = kind_ == TargetKind::Points
                                            ? tangentBasis(normal)[0]
                                            : decodeAngle(sampleNormal, record.angle);
  Eigen::Vector3d tangent = sampleTangent - sampleTangent.dot(normal) * normal;
  tangent = tangent.norm() > 1e-9 ? Eigen::Vector3d(tangent.normalized()) : tangentBasis(normal)[0];
  a.tangent = frame_.toWorldDirection(tangent);
  if (kind_ == TargetKind::Surface) {
    a.k1 = decodeHalf(record.c0) / frame_.voxelSize();
    a.k2 = decodeHalf(record.c1) / frame_.voxelSize();
  } else if (kind_ == TargetKind::Curve) {
    a.k1 = decodeHalf(record.c0) / frame_.voxelSize();
    if (a.k1 > 0.0) {
      a.principalNormal = frame_.toWorldDirection(decodeAngle(sampleTangent, record.c1));
    }
  }
  return a;
}

}  // namespace d2vdb::detail
