#include "d2vdb/spline/SurfaceGeometry.h"

#include <Eigen/Geometry>

#include <cmath>

namespace d2vdb {

SurfaceFrame surfaceFrame(const SurfaceDerivatives& d) {
  SurfaceFrame frame;
  frame.point = d.point;
  const Eigen::Vector3d cross = d.du.cross(d.dv);
  const double lengthU = d.du.norm();
  const double lengthV = d.dv.norm();
  const double area = cross.norm();
  if (!(area > 1e-12 * (lengthU * lengthU + lengthV * lengthV))) {
    frame.regular = false;
    const Eigen::Vector3d along = lengthU > 0.0 ? d.du : d.dv;
    frame.normal = along.norm() > 0.0 ? along.unitOrthogonal() : Eigen::Vector3d::UnitZ();
    frame.e1 = frame.normal.unitOrthogonal();
    frame.e2 = frame.normal.cross(frame.e1);
    return frame;
  }
  const Eigen::Vector3d n = cross / area;
  frame.normal = n;
  // Orthonormal tangent basis t1 = Su / |Su|, t2 = n x t1; in it [Su Sv] = [t1 t2] J with J upper
  // triangular. The shape operator in that basis is the symmetric B = J^-T II J^-1, where II is
  // the second fundamental form with respect to n (normal curvature II / I).
  const Eigen::Vector3d t1 = d.du / lengthU;
  const Eigen::Vector3d t2 = n.cross(t1);
  const double j11 = lengthU;
  const double j12 = t1.dot(d.dv);
  const double j22 = t2.dot(d.dv);
  const double l = d.duu.dot(n);
  const double m = d.duv.dot(n);
  const double nn = d.dvv.dot(n);
  // J^-1 = [[1/j11, -j12/(j11 j22)], [0, 1/j22]].
  Eigen::Matrix2d inverse;
  inverse << 1.0 / j11, -j12 / (j11 * j22), 0.0, 1.0 / j22;
  Eigen::Matrix2d second;
  second << l, m, m, nn;
  // The curvatures of the frame's convention are those of -II.
  const Eigen::Matrix2d b = -(inverse.transpose() * second * inverse);
  const double a11 = b(0, 0);
  const double a22 = b(1, 1);
  const double a12 = 0.5 * (b(0, 1) + b(1, 0));
  const double mean = 0.5 * (a11 + a22);
  const double half = 0.5 * (a11 - a22);
  const double radius = std::hypot(half, a12);
  frame.k1 = mean + radius;
  frame.k2 = mean - radius;
  // Eigenvector of the larger eigenvalue: angle theta with tan(2 theta) = 2 a12 / (a11 - a22).
  if (radius <= 1e-14 * (std::abs(mean) + radius) || radius == 0.0) {
    frame.e1 = t1;
  } else {
    const double theta = 0.5 * std::atan2(a12, half);
    frame.e1 = std::cos(theta) * t1 + std::sin(theta) * t2;
  }
  frame.e2 = n.cross(frame.e1);
  return frame;
}

SurfaceFrame surfaceFrame(const BSplineSurface& surface, double u, double v) {
  return surfaceFrame(surface.derivatives(u, v));
}

}  // namespace d2vdb
