// Internal to the support module: the tables and kernels that evaluate a support function and its
// derivatives at many normals.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/support/SupportFunction.h"

namespace d2vdb::detail {

/// Normals are evaluated in blocks of this many (the last block padded), so a normal's result
/// depends only on that normal, never on how the work was split between threads.
inline constexpr int kSupportBlock = 64;

/// Quantities evaluated per normal: h, grad P (3), Hess P (xx, xy, xz, yy, yz; zz = -xx - yy
/// since P is harmonic), with P the solid-harmonic extension of h. (P - n . grad P, which the
/// radii need, follows from h and grad P.)
enum SupportQuantity : int {
  kValue = 0,
  kGradX = 1,
  kGradY = 2,
  kGradZ = 3,
  kHessXX = 4,
  kHessXY = 5,
  kHessXZ = 6,
  kHessYY = 7,
  kHessYZ = 8,
  kQuantityCount = 9,
};

// Normals evaluated together in one SIMD register: two with the GCC/Clang vector extensions
// (SSE2 on x86-64, NEON on AArch64), else one.
#if defined(__GNUC__)
inline constexpr int kLanes = 2;
typedef double Lanes __attribute__((vector_size(2 * sizeof(double))));
#else
inline constexpr int kLanes = 1;
using Lanes = double;
#endif

/// The quantities of one block of normals: values[q][i] is quantity q at normal i.
struct SupportBlockValues {
  double values[kQuantityCount][kSupportBlock];
};

/// The evaluation tables of one support function.
///
/// Every quantity q is a sum over harmonics, sum_lm t_q(l, m) Y_l^m, and Y_l^{+-m} =
/// Lambda_l^m(z) (Re, Im)((x + i y)^m) (SphericalHarmonics.h). So for each order m the kernel
/// runs the three-term recurrence of Lambda_l^m over l once per normal and accumulates
/// A_q^m = sum_l t_q(l, m) Lambda_l^m and B_q^m = sum_l t_q(l, -m) Lambda_l^m in registers, then
/// adds A_q^m Re + B_q^m Im: every harmonic value is computed once and used for all quantities,
/// without storing the harmonics.
struct SupportEvaluator {
  int degree = 0;
  /// For order m and degree l >= m, the record at recordOffset[m] + (l - m) * kRecordSize: the
  /// recurrence coefficients (a, b) of Lambda_l^m (for l = m: the constant Lambda_m^m and 0),
  /// the coefficients t_q(l, m) (cosine part, q = 0..8), then t_q(l, -m) (sine part; zero for
  /// m = 0); zero where quantity q does not reach degree l. Each number is stored kLanes times
  /// (ready to load into a SIMD register).
  static constexpr int kRecordSize = (2 + 2 * kQuantityCount) * kLanes;
  std::vector<double> records;
  std::vector<std::size_t> recordOffset;

  SupportEvaluator(int degree, const Eigen::VectorXd& coefficients);

  /// The quantities at `count` (1..kSupportBlock) normals already normalised, into `out`
  /// (entries of normals beyond `count` unspecified). With `pointsOnly`, only kValue and the
  /// gradient are computed. Each normal's result depends on that normal only, bit for bit.
  void evaluateBlock(int count, const Eigen::Vector3d* normals, SupportBlockValues& out,
                     bool pointsOnly) const;
};

/// Assembles a SupportPoint from the quantities of normal `i` of a block.
SupportPoint assembleSupportPoint(const Eigen::Vector3d& normal, const SupportBlockValues& block,
                                  int i);

/// An orthonormal tangent frame (e1, e2) of the unit vector n with (e1, e2, n) right-handed,
/// continuous except across n_z = 0 (Duff et al., "Building an Orthonormal Basis, Revisited",
/// JCGT 6(1), 2017).
void tangentFrame(const Eigen::Vector3d& n, Eigen::Vector3d& e1, Eigen::Vector3d& e2);

}  // namespace d2vdb::detail
