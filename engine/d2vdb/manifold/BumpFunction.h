// The C-infinity cut-off function of the chart weights of a parametric pseudo-manifold.
#pragma once

namespace d2vdb {

/// The value and the first three derivatives of a scalar function of one variable.
struct BumpValue {
  double value = 0.0;
  double first = 0.0;
  double second = 0.0;
  double third = 0.0;
};

/// Where the chart weight starts to fall, as a fraction of the chart radius: a quarter, as in
/// Siqueira, Xu, Gallier, Nonato, Morera, Velho, "A new construction of smooth surfaces from
/// triangle meshes using parametric pseudo-manifolds", Computers & Graphics 33(3), 2009.
inline constexpr double kBumpInner = 0.25;

/// The cut-off xi(t) of the chart weights, t being the distance from the chart centre divided
/// by the chart radius (dimensionless):
///
///   xi(t) = 1                   for t <= 1/4,
///   xi(t) = 0                   for t >= 1,
///   xi(t) = 1 / (1 + exp(2 s))  otherwise, with s = 1 / (1 - H) - 1 / H, H = (t - 1/4) / (3/4).
///
/// s runs from -infinity to +infinity as t goes from 1/4 to 1, so xi falls monotonically from 1
/// to 0 and every derivative vanishes at both ends: xi is C-infinity on the whole line. At the
/// midpoint t = 5/8 (H = 1/2, s = 0) xi = 1/2 exactly. Where exp(2 s) over- or underflows the
/// value is the limit (0 or 1) with zero derivatives, which is exact to double precision.
/// Returns xi and its first three derivatives with respect to t. Never throws; NaN gives NaN.
BumpValue chartBump(double t);

}  // namespace d2vdb
