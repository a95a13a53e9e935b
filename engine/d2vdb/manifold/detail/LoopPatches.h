// Internal: the exact pieces of the Loop limit surface. A face whose three corners have degree 6
// is a quartic box-spline patch of the 12 vertices around it; a face with one extraordinary
// corner is evaluated exactly by subdividing its (N + 6)-vertex neighbourhood until the point
// lies in a regular sub-patch (Stam, "Evaluation of Loop subdivision surfaces", SIGGRAPH 1998
// course notes: the same sub-patch decomposition, here with the subdivision matrix applied
// directly instead of through its eigenvectors).
#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

#include "d2vdb/manifold/detail/TriangleBezier.h"

namespace d2vdb::detail {

/// Loop's vertex weight beta(N) = (5/8 - (3/8 + cos(2 pi / N) / 4)^2) / N.
double loopBeta(int valence);

/// The 12 control vertices of a regular patch over the triangle (p0, p1, p2), counter-clockwise,
/// listed by their positions in the regular triangular lattice in which p0 = (0, 0),
/// p1 = (1, 0), p2 = (0, 1) (coordinates along the lattice directions (1, 0) and
/// (1/2, sqrt(3)/2)): (0,0) (1,0) (0,1) (-1,0) (0,-1) (1,-1) (-1,1) (2,0) (1,1) (2,-1) (0,2)
/// (-1,2).
inline constexpr int kRegularControlCount = 12;
inline constexpr std::array<std::array<int, 2>, kRegularControlCount> kRegularLattice = {{{0, 0},
                                                                                          {1, 0},
                                                                                          {0, 1},
                                                                                          {-1, 0},
                                                                                          {0, -1},
                                                                                          {1, -1},
                                                                                          {-1, 1},
                                                                                          {2, 0},
                                                                                          {1, 1},
                                                                                          {2, -1},
                                                                                          {0, 2},
                                                                                          {-1, 2}}};

/// The quartic Bézier net (15 points, TriangleBezier layout) of the regular patch as a fixed
/// 15 x 12 matrix applied to the 12 control vertices. Derived once at run time from the
/// subdivision rules alone: two steps of Loop's regular rules on a lattice, Loop's limit mask
/// (1/2 the vertex, 1/12 each neighbour) at the 15 level-2 vertices (i/4, j/4), i + j <= 4, and the
/// quartic interpolating those limit values (the patch is a quartic polynomial, so this is exact).
const Eigen::Matrix<double, 15, kRegularControlCount>& regularPatchMatrix();

/// The quartic net of a regular patch from its 12 control points.
std::array<Eigen::Vector3d, 15> regularNet(const std::array<Eigen::Vector3d, 12>& controls);

/// Subdivision matrices of the neighbourhood of a triangle (c, n1, n2) whose corner c has valence
/// N and whose corners n1, n2 are regular. Template order (K = N + 6 vertices): c, the neighbours
/// n1..nN of c counter-clockwise, then b, a, m (the neighbours of n1 after n_N, counter-clockwise)
/// and d, e (the neighbours of n2 after m). One subdivision step maps the template to the
/// template of the sub-triangle at c (`step`, K x K); `extra` (6 x K) gives the six further
/// vertices of the finer level that the three regular sub-patches need: the edge points of n1-b,
/// n1-a, n1-m, n2-m, n2-d, n2-e.
struct ExtraordinaryTemplate {
  int valence = 0;
  Eigen::MatrixXd step;
  Eigen::MatrixXd extra;
  /// For each regular sub-patch T1 (at n1), T2 (centre), T3 (at n2): its 12 control vertices as
  /// indices into the finer level's template followed by the six extra vertices (index K + i).
  std::array<std::array<int, 12>, 3> subPatch;
  /// For each sub-patch: its quartic Bézier net (15 points) from the coarser level's template,
  /// regularPatchMatrix() x (selection of subPatch[t]) x [step; extra], 15 x K.
  std::array<Eigen::MatrixXd, 3> subPatchNet;
  /// Limit position weights of c (1 - N chi) and of each neighbour (chi), chi = 1 / (3 / (8 beta)
  /// + N).
  double limitCenter = 0.0;
  double limitNeighbor = 0.0;

  explicit ExtraordinaryTemplate(int valence);
  int size() const { return valence + 6; }
};

}  // namespace d2vdb::detail
