// Fitting tensor-product B-spline surfaces by squared distance minimisation (Pottmann,
// Leopoldseder and Hofer 2002): SDM I on targets that answer squared-distance approximants
// (fields of level sets, meshes, point sets; exact surface targets; offsets), SDM II on point
// clouds (errors orthogonal to the active surface, after Wang, Pottmann and Liu 2006).
#pragma once

#include <Eigen/Core>

#include <cstdint>
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
/// Throws InputError for invalid options, an estimated memory need above options.budget
/// (enforceSurfaceFitBudget()), an initial surface whose control points all coincide,
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
/// (3 per control point), an estimated memory need above options.budget, invalid options, or an
/// initial surface whose control points all coincide.
SurfaceFitResult fitSurfaceToPoints(const BSplineSurface& initial,
                                    const std::vector<Eigen::Vector3d>& points,
                                    const SurfaceFitOptions& options = {});

/// Memory per sensor of SDM I (or data point of SDM II) in a surface fit, in bytes: its basis
/// weights and indices, parameters, approximant, quadratic form, rank-one terms and the measured
/// distances. Measured 780 bytes (peak RSS of 'd2vdb fit-surface' on volumes/torus.vdb with
/// --ctrl 20,20 and --sensors 6 against 24: 14,400 against 230,400 sensors), rounded up.
inline constexpr double kSurfaceFitBytesPerSensor = 1000.0;

/// Memory of a surface fit's linear systems, in bytes per N^1.5 for N control points: the sparse
/// Cholesky factor of a two-dimensional net of control points fills in like N^1.5 (nested
/// dissection; George 1973, "Nested dissection of a regular finite element mesh"), plus the
/// indefinite fallback's LDLT. Fitted to the peak RSS of 'd2vdb fit-surface' on volumes/torus.vdb
/// from --ctrl 10,10 to 60,60 (518 MB at 60,60 with 100 iterations, of which this term is 367 MB).
inline constexpr double kSurfaceFitBytesPerControlPoint15 = 1700.0;

/// The number of sensors fitSurface() places on `surface` with `sensorsPerSpan` per knot span
/// and direction: (spans_u * s + 2 [open u]) * (spans_v * s + 2 [open v]). A double, so that
/// absurd requests do not overflow.
double surfaceSensorCount(const BSplineSurface& surface, int sensorsPerSpan);

/// Estimated peak memory (bytes) of fitting `surface` with `sensors` sensors (SDM I:
/// surfaceSensorCount(); SDM II: the data points), beyond the target's own memory:
/// kSurfaceFitBytesPerSensor * sensors + kSurfaceFitBytesPerControlPoint15 * N^1.5. Within a
/// factor of two of the measured figures above.
double estimateSurfaceFitMemoryBytes(const BSplineSurface& surface, double sensors);

/// Throws InputError, before anything is allocated, when estimateSurfaceFitMemoryBytes() exceeds
/// budget.maxMemoryBytes. `sensorsPerSpan` > 0 (SDM I) makes the message name the largest
/// --sensors that fits, or, when none does, the control points that would; 0 (SDM II, `sensors`
/// data points) names the control points.
void enforceSurfaceFitBudget(const BSplineSurface& surface, double sensors, int sensorsPerSpan,
                             const ResourceBudget& budget);

}  // namespace d2vdb
