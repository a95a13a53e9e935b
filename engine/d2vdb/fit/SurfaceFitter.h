// Fitting tensor-product B-spline surfaces by squared distance minimisation (Pottmann,
// Leopoldseder and Hofer 2002): SDM I on targets that answer squared-distance approximants
// (fields of level sets, meshes, point sets; exact surface targets; offsets), SDM II on point
// clouds (errors orthogonal to the active surface, after Wang, Pottmann and Liu 2006).
#pragma once

#include <Eigen/Core>

#include <vector>

#include "d2vdb/field/Approximant.h"
#include "d2vdb/field/SquaredDistanceTarget.h"
#include "d2vdb/fit/SurfaceFit.h"
#include "d2vdb/spline/BSplineSurface.h"

namespace d2vdb {

/// SDM I: deforms `initial` (knots fixed; open or closed in u and v; any degrees, (1, n) for ruled
/// surfaces) so that its sensors come close to `target`.
///
/// Each iteration places options.sensorsPerSpan^2 sensors per knot cell at fixed parameters
/// (evenly in each knot span, plus the boundary lines of open directions), asks the target for the
/// approximant at every sensor (parallel), forms each sensor's quadratic by options.method
/// (fitForm), solves the quadratic model (mean over sensors + thin-plate/membrane smoothing) and
/// controls the
/// step: a line search on the true objective mean_k target.squaredDistanceAt(x_k) + smoothing for
/// PDM, SDM and TDM+PDM, a Levenberg-Marquardt schedule for TDM. It stops as SurfaceFitOptions
/// says and states why. Deterministic: bitwise identical for any thread count.
///
/// Throws InputError for invalid options, an initial surface whose control points all coincide,
/// or a sensor of the initial surface outside target.domain() (the message names the sensor and
/// the domain). Later iterates that would leave the domain are treated as failed steps.
SurfaceFitResult fitSurface(const BSplineSurface& initial, const SquaredDistanceTarget& target,
                            const SurfaceFitOptions& options = {});

/// The approximant of the squared distance from `dataPoint` to the active surface, attached to
/// the surface at the data point's footpoint S(u, v) (SDM II): kind Surface, footpoint S(u, v),
/// the surface's unit normal (along Su x Sv), principal direction e1 and curvatures k1 >= k2
/// there (surfaceFrame()), signed distance (dataPoint - S) . normal. Its form(term), read with
/// the roles of footpoint and data point exchanged, is the SDM II error term:
/// sum_i w_i ((S - X) . e_i)^2 + ((S - X) . n)^2 with w_i = max(0, d k_i / (1 + d k_i)). A
/// footpoint on the boundary of an open direction, or where the surface is not regular, gets
/// kFlagEndPoint (a point distance: normal toward the data point, PDM form). Throws InputError
/// for a parameter outside an open direction's domain.
Approximant surfaceApproximantAt(const BSplineSurface& surface, double u, double v,
                                 const Eigen::Vector3d& dataPoint);

/// SDM II: fits `initial` (knots fixed) to the point cloud `points`. Every iteration projects each
/// data point onto the current surface (SurfaceProjector::nearest, started from its previous
/// footpoint, in parallel), forms its error term from surfaceApproximantAt() under
/// options.method (PDM: the classic point-distance fit with parameter correction; TDM; SDM;
/// TDM+PDM) and solves the quadratic model for the surface points S(u_k, v_k) near the data. The
/// line search (or TDM's damping) uses the true objective mean_k min_(u,v) |S(u, v) - X_k|^2 +
/// smoothing. Deterministic for any thread count.
///
/// Throws InputError for an empty cloud, a non-finite coordinate, fewer data points than unknowns
/// (3 per control point), invalid options, or an initial surface whose control points all
/// coincide.
SurfaceFitResult fitSurfaceToPoints(const BSplineSurface& initial,
                                    const std::vector<Eigen::Vector3d>& points,
                                    const SurfaceFitOptions& options = {});

}  // namespace d2vdb
