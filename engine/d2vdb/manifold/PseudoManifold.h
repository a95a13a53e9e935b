// A C-infinity surface from a closed triangle mesh: the parametric pseudo-manifold of Siqueira,
// Xu, Gallier, Nonato, Morera and Velho (Computers & Graphics 33(3), 2009).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "d2vdb/core/Progress.h"
#include "d2vdb/manifold/ChartAtlas.h"
#include "d2vdb/manifold/HalfEdgeMesh.h"
#include "d2vdb/manifold/SourceSurface.h"

namespace d2vdb {

/// Construction parameters of a PseudoManifold.
struct PseudoManifoldOptions {
  /// Cap of the shape functions' bidegree: a vertex of degree n gets a tensor-product Bézier
  /// patch of bidegree min(n + 1, maxBidegree) in both directions (the reference construction
  /// uses n + 1). Range 2..12.
  int maxBidegree = 7;
  /// Fitting grid density: the chart's bounding square is sampled on a cell-centred grid with
  /// samplesPerControl * (bidegree + 1) points per side, of which those inside the chart disc
  /// are used. Range 2..8.
  int samplesPerControl = 2;
  /// Refuse (InputError, before allocating) when the control points would take more bytes than
  /// this: 3 doubles per control point, (bidegree + 1)^2 per vertex, each row of bidegree + 1
  /// padded to an even count (1536 bytes at bidegree 7, 1344 at bidegree 6).
  std::size_t maxBytes = std::size_t{8} << 30;
};

/// How much a surface evaluation computes.
enum class Derivatives : std::uint8_t {
  None = 0,    ///< position only
  First = 1,   ///< position and unit normal
  Second = 2,  ///< position, normal, principal curvatures and directions
};

/// A point of the smooth surface with its differential geometry (world units).
/// normal: unit, outward for a counter-clockwise (seen from outside) mesh. k1 >= k2: principal
/// curvatures (1 / world units), positive where the surface bends away from the normal (a sphere
/// of radius R has k = 1/R); e1, e2 = normal x e1: unit principal directions. Fields beyond the
/// requested Derivatives are left at their defaults.
struct SmoothPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double k1 = 0.0;
  double k2 = 0.0;
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();
  Eigen::Vector3d e2 = Eigen::Vector3d::UnitY();
};

/// Position with first and second derivatives with respect to two parameters (s, t):
/// d[0] = dX/ds, d[1] = dX/dt, dd[0] = d2X/ds2, dd[1] = d2X/dsdt, dd[2] = d2X/dt2.
struct SmoothDerivatives {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d d[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  Eigen::Vector3d dd[3] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                           Eigen::Vector3d::Zero()};
};

/// SmoothDerivatives with the third derivatives: ddd[0] = d3X/ds3, ddd[1] = d3X/ds2dt,
/// ddd[2] = d3X/dsdt2, ddd[3] = d3X/dt3.
struct SmoothThirdDerivatives : SmoothDerivatives {
  Eigen::Vector3d ddd[4] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                            Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
};

/// The differential geometry (normal, principal curvatures and directions) of a parametrised
/// surface from its first and second derivatives, conventions as in SmoothPoint. The tangent
/// vectors must be linearly independent (the result is not finite otherwise).
SmoothPoint surfaceGeometry(const SmoothDerivatives& derivatives);

/// How PseudoManifold::project() finishes.
struct SmoothProjectionOptions {
  /// When the last Newton step is below 1e-6 of the chart radius, take the derivatives where
  /// it ends from a second-order Taylor expansion of those before it (position, first
  /// derivatives; the second derivatives are kept) instead of evaluating the surface there:
  /// one evaluation fewer. The footpoint is the same; position and normal are exact to
  /// O(step^2) of the chart radius (round-off), the curvatures to O(step), i.e. about 1e-6 of
  /// their value. Off: the surface is evaluated at the footpoint.
  bool extrapolateLastStep = false;
  /// Finish with a cubic model: where a Newton step is expected to end near the footpoint, the
  /// surface is evaluated there with third derivatives; when the next Newton step from that
  /// iterate is below `cubicFinishStep` of the chart radius, the footpoint is taken as the
  /// minimum of the distance to the cubic Taylor model of the surface at the iterate (found by
  /// Newton's method on the model, no evaluation), and position, first and second derivatives
  /// are carried there along the model (errors O(step^4), O(step^3) and O(step^2) of the chart
  /// radius): the evaluation at the footpoint goes. The footpoint then lies within about
  /// step^3 of the radius of the exact one (the model's error in the gradient of the distance),
  /// the curvatures within about step^2 of their value. Off: the iteration runs on until a
  /// Newton step predicts convergence to 1e-12 of the radius.
  bool cubicFinish = false;
  /// Largest Newton step (a fraction of the chart radius) that cubicFinish replaces by the cubic
  /// model's minimum.
  double cubicFinishStep = 1e-3;
  /// With cubicFinish, project(x, nearby) starts from the minimum of the distance to the nearby
  /// projection's cubic model (Projection::model) instead of a Newton step from its footpoint:
  /// its error is of third order in the distance between the two footpoints, not of second.
  /// When that minimum lies within cubicFinishStep of the chart radius of the model's origin it
  /// is the answer (no evaluation; the same accuracy as cubicFinish); when it lies within 0.15
  /// of the radius of the origin and its distance exceeds stopBeyond by a margin (2 % within a
  /// tenth of the radius, beyond that 2 % times (|move| / (radius / 10))^4, up to 10 %) the
  /// projection stops `beyond` (no evaluation; the model's error, which grows like the margin,
  /// is far below it); else the iteration continues from it (the step checked like any other).
  /// firstStepCorrection is then not used.
  bool startFromModel = false;
  /// Stop as soon as the distance is certainly above this (world units): when a Newton step
  /// below 1e-2 of the chart radius leaves, by four times the decrease the quadratic model
  /// predicts, a distance above it. The projection then ends unconverged with `beyond` set.
  /// Infinite: never.
  double stopBeyond = std::numeric_limits<double>::infinity();
  /// A second-order start for project() from a nearby projection: a shift (chart coordinates of
  /// the chart of `vertex`) added to the first Newton step when that step is taken in this chart.
  /// Typically Projection::firstStepMiss of the nearby projection, when it was itself projected
  /// from its own neighbour by the same displacement: the miss of a Newton step from a footpoint
  /// changes only to third order from one voxel to the next, so the corrected start lies much
  /// nearer the footpoint. Only the start changes; the iteration and its convergence test are
  /// the same (the corrected step is checked like any other and undone if it goes uphill).
  std::optional<ChartPoint> firstStepCorrection;
};

/// The parametric pseudo-manifold (PPS) of a closed mesh fitted to a source surface: a
/// C-infinity surface that approximates the source, evaluated at (face, barycentric) points.
///
/// Construction (Siqueira et al. 2009): every vertex v of degree n has a chart, the open disc of
/// radius cos(pi / n) (ChartAtlas.h), and a shape function psi_v: a tensor-product Bézier patch
/// of bidegree d = min(n + 1, maxBidegree) over the chart's bounding square [-cos(pi/n),
/// cos(pi/n)]^2, fitted by least squares to the source surface at the grid points of that
/// square inside the disc. A grid point p is sent to the face point of p (ChartAtlas::fromChart),
/// i.e. through the same polar map the evaluation uses, so every chart approximates the source at
/// the same surface point (the reference construction maps samples affinely from the n-gon's
/// sectors, which shifts the charts' contributions against each other for n != 6). The design
/// matrix depends only on n, so its pseudo-inverse is computed once per degree (Householder QR,
/// not the normal equations, and shared by every surface the process builds); each vertex then
/// costs one matrix product.
///
/// Weights: gamma_v(p) = xi(|p| / cos(pi / n)) with the C-infinity cut-off xi of BumpFunction.h
/// (1 within a quarter of the chart radius, 0 from the rim on). The surface point of a face point
/// is sum_v gamma_v(p_v) psi_v(p_v) / sum_v gamma_v(p_v) over the face's corners v whose chart
/// contains the point (p_v its chart point); at least one does, as the three discs cover the
/// face. Each term is a composition of C-infinity maps in any chart's coordinates (a weight
/// vanishes with all derivatives before its chart's rim), so the surface is C-infinity; on an edge
/// only the edge's two charts contribute and both faces compute the same chart points, so
/// evaluations from either side agree to round-off.
///
/// Differential geometry is computed in the coordinates of the chart of the face corner nearest
/// to the point, where the parametrisation is smooth, with exact derivatives (chain rule through
/// the polar maps, the Bézier patches and the weights). Construction and batch evaluation run in
/// parallel (TBB) and give the same results for any thread count. Immutable; thread-safe.
class PseudoManifold {
 public:
  /// Builds the PPS of `source` (which is only read during construction). Throws InputError for
  /// options out of range or a surface whose control points would exceed options.maxBytes.
  /// `progress` reports the fitting stage.
  explicit PseudoManifold(const SourceSurface& source, const PseudoManifoldOptions& options = {},
                          const ProgressCallback& progress = {});
  ~PseudoManifold();
  PseudoManifold(PseudoManifold&&) noexcept;
  PseudoManifold& operator=(PseudoManifold&&) noexcept;

  const HalfEdgeMesh& mesh() const { return *mesh_; }
  const ChartAtlas& atlas() const { return atlas_; }
  const PseudoManifoldOptions& options() const { return options_; }
  /// Name of the source surface ("loop" or "pn").
  const std::string& sourceName() const { return sourceName_; }

  /// Bidegree of the shape function of `vertex` (0 for a vertex no face uses).
  int bidegree(HalfEdgeMesh::Index vertex) const;
  /// Control points b_jk (j along the chart's x, k along y) of the shape function of `vertex`,
  /// index j * (bidegree + 1) + k.
  std::vector<Eigen::Vector3d> controlPoints(HalfEdgeMesh::Index vertex) const;
  /// Condition number (2-norm) of the least-squares design matrix for vertices of `degree` (0 if
  /// no vertex has that degree).
  double fitConditionNumber(int degree) const;
  /// Number of fitting samples of a vertex of `degree` (0 if no vertex has that degree).
  int fitSampleCount(int degree) const;

  /// The shape function psi_v at chart point p (any p; a polynomial).
  Eigen::Vector3d shapeFunction(const ChartPoint& point) const;
  /// The weight gamma_v(p) of the chart of point.vertex.
  double weight(const ChartPoint& point) const;

  /// The surface point at a face point (barycentric coordinates of a point of the face).
  Eigen::Vector3d position(const FacePoint& point) const;
  /// The surface point with the requested differential geometry.
  SmoothPoint evaluate(const FacePoint& point, Derivatives derivatives) const;
  /// evaluate() for every point, in parallel; result i for points[i]. Throws InputError for a face
  /// index out of range (the first in index order).
  std::vector<SmoothPoint> evaluate(const std::vector<FacePoint>& points,
                                    Derivatives derivatives) const;
  /// The same into `out` (resized to points.size(); its storage is reused).
  void evaluate(const std::vector<FacePoint>& points, Derivatives derivatives,
                std::vector<SmoothPoint>& out) const;

  /// Derivatives with respect to the face's barycentric coordinates (b1, b2) (b0 = 1 - b1 - b2).
  /// Nothing at a corner of degree != 6, where the map from the face to the chart (angles scaled
  /// by 6 / n) is not differentiable: use chartDerivatives() there.
  std::optional<SmoothDerivatives> faceDerivatives(const FacePoint& point) const;
  /// Derivatives with respect to the chart coordinates of the face's corner `corner` (0..2),
  /// at a point of the face inside that chart (ChartAtlas::inChart). Smooth everywhere in the
  /// chart, centre included. Throws InputError when the point is not in the chart.
  SmoothDerivatives chartDerivatives(const FacePoint& point, int corner) const;
  /// chartDerivatives() with the third derivatives (exact chain rules through the polar maps,
  /// the Bézier patches, the weights and their quotient). Throws InputError when the point is
  /// not in the chart.
  SmoothThirdDerivatives chartThirdDerivatives(const FacePoint& point, int corner) const;

  /// The closest surface point found by Newton's method on |X - x|^2 from `start`, in the
  /// coordinates of the chart nearest to the current iterate (walking across faces and charts).
  struct Projection {
    FacePoint point;                                     ///< where it ended
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< surface point there
    double distance = 0.0;                               ///< |x - position|
    SmoothPoint geometry;  ///< position, normal, curvatures and directions there
    /// Derivatives of the surface at `point` with respect to the chart coordinates of the face's
    /// corner `chartCorner` (0..2), the corner with the largest barycentric coordinate there.
    SmoothDerivatives derivatives;
    int chartCorner = 0;
    /// `point` in the coordinates of that chart (ChartAtlas::toChart(point, chartCorner)).
    Eigen::Vector2d chartPoint = Eigen::Vector2d::Zero();
    /// Where the plain Newton step from a given nearby projection (its first step, without any
    /// firstStepCorrection) would have ended short of the footpoint: footpoint minus that end,
    /// in the chart of its `vertex` (the chart the step was taken in). Empty when the projection
    /// did not start from a nearby projection, did not end converged in that chart, the step was
    /// clipped (to its bound or the chart) or an unchecked first step had to be undone.
    std::optional<ChartPoint> firstStepMiss;
    /// The cubic Taylor model of the surface the footpoint was found on
    /// (SmoothProjectionOptions::cubicFinish): the point it expands about, in the chart the
    /// derivatives refer to, and the surface's derivatives up to the third there. Empty when the
    /// projection did not end on such a model. A projection from a nearby one that stops beyond
    /// at the nearby footpoint (before any step) keeps the nearby projection's model.
    struct CubicModel {
      ChartPoint origin;
      SmoothThirdDerivatives derivatives;
    };
    std::optional<CubicModel> model;
    int iterations = 0;  ///< surface evaluations made (the start's included unless it was given)
    /// The footpoint is a minimum of the distance to within 1e-12 of the chart radius (see
    /// project()), or no step lowered the distance; with SmoothProjectionOptions::cubicFinish or
    /// startFromModel, to within the cubic model's accuracy where it ended on one (`model`).
    bool converged = false;
    /// Stopped early: the distance is certainly above SmoothProjectionOptions::stopBeyond (the
    /// footpoint, position and derivatives are those of the last iterate; `geometry` then holds
    /// only the position, its other members keep their defaults).
    bool beyond = false;
  };
  /// Local projection of `x` onto the surface from `start` (a local minimum of the distance near
  /// start, not necessarily the global one). Newton steps (Gauss-Newton where the Hessian of the
  /// squared distance is not positive definite) of at most half the chart radius. Newton steps
  /// below 1e-4 of the radius are always taken; until one has gone uphill, Newton steps below a
  /// tenth of the radius are taken and checked by the next iterate's distance (an uphill one is
  /// undone); other steps are halved until the distance falls. Converged: a Newton step below
  /// 1e-12 of the chart radius (the iterate is the answer), or a Newton step s_k after which the
  /// quadratic convergence observed so far predicts a next step below 1e-12 of the radius
  /// (|s_k|^3 / |s_(k-1)|^2, or 10 |s_k|^2 / radius for the first step): that step is taken and
  /// the geometry is evaluated where it ends. Throws InputError for non-finite x.
  Projection project(const Eigen::Vector3d& x, const FacePoint& start,
                     const SmoothProjectionOptions& options = {}) const;
  /// project() from the footpoint of a projection already made onto this surface (of a nearby
  /// point, typically): the first Newton step is taken from that projection's derivatives, without
  /// evaluating the surface there. Throws InputError for non-finite x or a projection whose face
  /// or chart corner does not exist (or whose chart point is not finite).
  Projection project(const Eigen::Vector3d& x, const Projection& nearby,
                     const SmoothProjectionOptions& options = {}) const;
  /// project(x, nearby, options) written into `result` (every member set, no copy of a returned
  /// projection), for callers that keep many projections. Throws InputError as that does, and
  /// when `result` is `nearby`.
  void project(const Eigen::Vector3d& x, const Projection& nearby,
               const SmoothProjectionOptions& options, Projection& result) const;
  /// Bytes held (control points, tables).
  std::size_t memoryBytes() const;

 private:
  struct DegreeFit;
  template <int Order>
  struct Evaluator;
  /// One projectFrom(): the state and phases of its Newton iteration.
  class ProjectionRun;

  const DegreeFit& fitFor(int degree) const;
  /// project() from `start`; when `nearby` is given it is a projection that ended at start,
  /// whose derivatives and chart point (in the chart of its corner chartCorner) are used.
  void projectFrom(const Eigen::Vector3d& x, const FacePoint& start, const Projection* nearby,
                   const SmoothProjectionOptions& options, Projection& result) const;
  /// The least-squares tables of one (degree, bidegree, density), computed once per process and
  /// shared (they do not depend on the mesh).
  static std::shared_ptr<const DegreeFit> sharedFit(int degree, int bidegree,
                                                    int samplesPerControl);

  std::shared_ptr<const HalfEdgeMesh> mesh_;
  ChartAtlas atlas_;
  PseudoManifoldOptions options_;
  std::string sourceName_;
  std::vector<std::shared_ptr<const DegreeFit>> fits_;  ///< index: vertex degree
  std::vector<std::size_t> controlOffset_;              ///< per vertex, into controls_ (doubles)
  std::vector<double> controls_;                        ///< x, y, z per control point
};

}  // namespace d2vdb
