// d2vdb's surface fitter beside OpenCASCADE's GeomAPI_PointsToBSplineSurface (OCCT, built only
// where its Debian packages are installed; tools/bench/CMakeLists.txt). The shape is an open patch
// of the torus R = 2, r = 0.5 about the z axis,
//   T(a, b) = ((R + r cos b) cos a, (R + r cos b) sin a, r sin b),  a in [0, pi/2], b in [0, pi]
// (a quarter of the major circle times the upper half of the tube: from the outer equator over
// the top to the inner equator, so it holds both elliptic and hyperbolic points).
//  - BM_Occt/tol_exp: GeomAPI_PointsToBSplineSurface on the 41 x 41 grid of exact samples
//    T(a_i, b_j) (uniform in a and b; TColgp_Array2OfPnt), degree exactly 3 (DegMin = DegMax = 3),
//    C2, Tol3D = 10^-tol_exp, default (chord-length) parametrisation. OCCT chooses its knots from
//    the tolerance; poles_u x poles_v is the control net it produced. One thread.
//  - BM_D2vdbPoints/tol_exp/start/threads: d2vdb SDM II (fitSurfaceToPoints, default options) on
//    the same 1681 samples as a point cloud, bicubic open x open with the net OCCT produced at that
//    tolerance (clamped uniform knots).
//  - BM_D2vdbField/tol_exp/start/threads: d2vdb SDM I (fitSurface, default options) on the torus's
//    level set (primitiveLevelSet, voxel 0.01, through the approximant field), same net.
//  - BM_D2vdbPatch/tol_exp/start/threads: SDM I on the patch itself as an exact target
//    (ExactPatchTarget: the torus's exact approximants on the patch, point distances to its edges
//    beyond them), same net. SDM I measures the distance from the surface to the target only, so
//    nothing in its objective makes an open surface span the whole patch (a smaller surface on the
//    torus is as close); coverage and edge_shift show where its edges end up.
//  - BM_D2vdbPointsToOcctRms/tol_exp/0/1: SDM II as above (start 0, one thread) stopped when its
//    RMS distance from the samples reaches OCCT's (distanceTolerance, cap 1000 iterations): the
//    time d2vdb needs to be as close to the samples as OCCT is; reached = 1 when it got there.
// The d2vdb start (start 0): the control net at the Greville abscissae of T with the wrong radii
// 1.7 and 0.8 over the same angles (the torus start, here open); start 1: the same with
// the right radii (what the fit reaches apart from the start).
//
// Each d2vdb benchmark iteration times the OCCT fit (one thread) right before the d2vdb fit, so
// both see the same machine load: occt_ms and ms are medians, ratio = ms / occt_ms. Times are wall
// times (manual). Accuracy, for every surface alike (OCCT's converted exactly to a d2vdb surface;
// conversion_error checks it against OCCT's own evaluation, corner_error its corners against the
// grid's):
//  - max_error, rms_error: exact distance |sqrt((rho - R)^2 + z^2) - r| to the analytic torus at
//    the points of a 201 x 201 grid over the fitted surface's whole parameter domain (edges
//    included) that lie over the patch (the torus point nearest to them has a in [0, pi/2] and b
//    in [0, pi]); inside = the fraction of the grid that does (1 when the surface does not
//    overhang the patch); max_error_all = the largest distance over the whole grid;
//  - coverage: the largest distance from 101 x 101 exact points of the patch (edges included) to
//    the fitted surface (exact nearest point), so a fit that lies on the torus but does not span
//    the patch shows;
//  - data_rms: SDM II, the RMS distance from the 1681 samples to the fit (the fitter's own figure);
//    OCCT, the same measured by exact projection; SDM I, the RMS distance of the sensors to the
//    target;
//  - edge_shift: the largest angle (radians of the major or the tube circle) between a
//    midpoint of one of the fitted surface's edges and the patch edge it should lie on.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Pnt.hxx>

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "BenchStatistics.h"
#include "common/ExactApproximant.h"
#include "d2vdb/field/AnalyticShapes.h"
#include "d2vdb/field/ApproximantField.h"
#include "d2vdb/field/Primitives.h"
#include "d2vdb/fit/SurfaceFitter.h"
#include "d2vdb/measure/SurfaceProjection.h"
#include "d2vdb/spline/BSplineSurface.h"
#include "d2vdb/spline/KnotVector.h"

namespace {

constexpr double kPi = 3.141592653589793238463;
constexpr double kMajor = 2.0, kMinor = 0.5;
constexpr double kStartA = 0.0, kEndA = kPi / 2;  // around the axis
constexpr double kStartB = 0.0, kEndB = kPi;      // around the tube, 0 on the outer equator
constexpr int kGridU = 41, kGridV = 41;           // the samples both fitters get

/// T(a, b) on the torus of radii `major` and `minor`.
Eigen::Vector3d torusPoint(double a, double b, double major = kMajor, double minor = kMinor) {
  const double rho = major + minor * std::cos(b);
  return {rho * std::cos(a), rho * std::sin(a), minor * std::sin(b)};
}

/// Exact distance from p to the torus (R = 2, r = 0.5): to the tube around the centre circle.
double torusDistance(const Eigen::Vector3d& p) {
  return std::abs(std::hypot(std::hypot(p.x(), p.y()) - kMajor, p.z()) - kMinor);
}

/// The grid of exact samples T(a_i, b_j), row-major (i along a).
const std::vector<Eigen::Vector3d>& gridSamples() {
  static const std::vector<Eigen::Vector3d> samples = [] {
    std::vector<Eigen::Vector3d> points;
    for (int i = 0; i < kGridU; ++i) {
      for (int j = 0; j < kGridV; ++j) {
        points.push_back(torusPoint(kStartA + (kEndA - kStartA) * i / (kGridU - 1),
                                    kStartB + (kEndB - kStartB) * j / (kGridV - 1)));
      }
    }
    return points;
  }();
  return samples;
}

/// 101 x 101 exact points of the patch, edges included (for the coverage).
const std::vector<Eigen::Vector3d>& patchPoints() {
  static const std::vector<Eigen::Vector3d> points = [] {
    std::vector<Eigen::Vector3d> result;
    for (int i = 0; i <= 100; ++i) {
      for (int j = 0; j <= 100; ++j) {
        result.push_back(torusPoint(kStartA + (kEndA - kStartA) * i / 100.0,
                                    kStartB + (kEndB - kStartB) * j / 100.0));
      }
    }
    return result;
  }();
  return points;
}

/// Torus angles (a, b) of the point of the torus nearest to p: a around the axis, b around the
/// tube (b in (-pi, pi], 0 on the outer equator).
double angleA(const Eigen::Vector3d& p) {
  return std::atan2(p.y(), p.x());
}
double angleB(const Eigen::Vector3d& p) {
  return std::atan2(p.z(), std::hypot(p.x(), p.y()) - kMajor);
}

/// The torus's level set, voxel 0.01, as an approximant field with its coarse levels (built once).
const d2vdb::ApproximantField& torusField() {
  static const d2vdb::ApproximantField field = [] {
    d2vdb::PrimitiveLevelSetOptions options;
    options.voxelSize = 0.01;
    options.halfWidth = 3;
    const d2vdb::Torus torus(Eigen::Vector3d::Zero(), kMajor, kMinor);
    return d2vdb::ApproximantField::fromLevelSet(d2vdb::primitiveLevelSet(torus, options));
  }();
  field.buildCoarseLevels();  // else the first fit that queries beyond the band builds them
  return field;
}

/// The patch itself as an exact target (SDM I without a field): where the torus point nearest to
/// x lies on the patch, the torus's exact approximant there (Torus::closestSurfacePoint); else the
/// nearest point of the patch's four edge arcs (closed form per arc), as a point distance
/// (kFlagEndPoint), which holds the fitted surface's edges to the patch's.
class ExactPatchTarget final : public d2vdb::SquaredDistanceTarget {
 public:
  d2vdb::TargetKind kind() const override { return d2vdb::TargetKind::Surface; }
  Eigen::AlignedBox3d domain() const override {
    return Eigen::AlignedBox3d(Eigen::Vector3d(-4, -4, -3), Eigen::Vector3d(4, 4, 3));
  }
  d2vdb::Approximant approximantAt(const Eigen::Vector3d& x) const override {
    const d2vdb::SurfacePoint s = torus_.closestSurfacePoint(x);
    const double a = angleA(s.point), b = angleB(s.point);
    if (a >= kStartA && a <= kEndA && b >= kStartB && b <= kEndB) {
      return d2vdb::test::approximantFrom(s, x);
    }
    Eigen::Vector3d best = Eigen::Vector3d::Zero();
    double bestDistance = std::numeric_limits<double>::infinity();
    const auto arc = [&](const Eigen::Vector3d& center, const Eigen::Vector3d& e1,
                         const Eigen::Vector3d& e2, double radius, double t0, double t1) {
      const Eigen::Vector3d w = x - center;
      const double t = std::clamp(std::atan2(w.dot(e2), w.dot(e1)), t0, t1);
      for (const double angle : {t, t0, t1}) {
        const Eigen::Vector3d p = center + radius * (std::cos(angle) * e1 + std::sin(angle) * e2);
        const double d = (x - p).norm();
        if (d < bestDistance) bestDistance = d, best = p;
      }
    };
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    for (const double a0 : {kStartA, kEndA}) {  // meridian arcs: tube circles at a = a0
      const Eigen::Vector3d radial(std::cos(a0), std::sin(a0), 0.0);
      arc(kMajor * radial, radial, z, kMinor, kStartB, kEndB);
    }
    for (const double b0 : {kStartB, kEndB}) {  // parallel arcs: circles at b = b0
      arc(Eigen::Vector3d(0, 0, kMinor * std::sin(b0)), Eigen::Vector3d::UnitX(),
          Eigen::Vector3d::UnitY(), kMajor + kMinor * std::cos(b0), kStartA, kEndA);
    }
    d2vdb::Approximant result;
    result.kind = d2vdb::TargetKind::Surface;
    result.origin = x;
    result.footpoint = best;
    result.flags |= d2vdb::kFlagEndPoint;
    result.distance = bestDistance;
    result.normal =
        bestDistance > 0 ? Eigen::Vector3d((x - best) / bestDistance) : Eigen::Vector3d(s.normal);
    result.tangent = result.normal.unitOrthogonal();
    return result;
  }
  std::string describe() const override { return "exact torus patch"; }

 private:
  d2vdb::Torus torus_{Eigen::Vector3d::Zero(), kMajor, kMinor};
};

/// The control net OCCT produced, and its time.
struct OcctFit {
  d2vdb::BSplineSurface surface;  // OCCT's surface converted exactly
  int degreeU = 0, degreeV = 0;
  double seconds = 0.0;
  double conversionError = 0.0;  // largest |OCCT Value - converted evaluate| at 11 x 11 points
  double cornerError = 0.0;      // largest distance of a surface corner from its grid corner
};

/// A flat knot vector from OCCT's distinct knots and multiplicities.
std::vector<double> flatKnots(const TColStd_Array1OfReal& knots,
                              const TColStd_Array1OfInteger& multiplicities) {
  std::vector<double> flat;
  for (int k = knots.Lower(); k <= knots.Upper(); ++k) {
    for (int m = 0; m < multiplicities(k); ++m) flat.push_back(knots(k));
  }
  return flat;
}

/// GeomAPI_PointsToBSplineSurface on gridSamples() with tolerance `tolerance`, timed (wall), and
/// its surface converted to a d2vdb surface (knots and poles copied; non-rational).
OcctFit occtFit(double tolerance) {
  TColgp_Array2OfPnt points(1, kGridU, 1, kGridV);
  const std::vector<Eigen::Vector3d>& samples = gridSamples();
  for (int i = 0; i < kGridU; ++i) {
    for (int j = 0; j < kGridV; ++j) {
      const Eigen::Vector3d& p = samples[static_cast<std::size_t>(i * kGridV + j)];
      points.SetValue(i + 1, j + 1, gp_Pnt(p.x(), p.y(), p.z()));
    }
  }
  const auto start = std::chrono::steady_clock::now();
  const GeomAPI_PointsToBSplineSurface fit(points, 3, 3, GeomAbs_C2, tolerance);
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  if (!fit.IsDone()) throw std::runtime_error("GeomAPI_PointsToBSplineSurface failed");
  const Handle(Geom_BSplineSurface)& s = fit.Surface();
  if (s->IsURational() || s->IsVRational() || s->IsUPeriodic() || s->IsVPeriodic()) {
    throw std::runtime_error("OCCT returned a rational or periodic surface");
  }
  TColStd_Array1OfReal knotsU(1, s->NbUKnots()), knotsV(1, s->NbVKnots());
  TColStd_Array1OfInteger multU(1, s->NbUKnots()), multV(1, s->NbVKnots());
  s->UKnots(knotsU);
  s->VKnots(knotsV);
  s->UMultiplicities(multU);
  s->VMultiplicities(multV);
  std::vector<Eigen::Vector3d> poles;
  for (int i = 1; i <= s->NbUPoles(); ++i) {
    for (int j = 1; j <= s->NbVPoles(); ++j) {
      const gp_Pnt& p = s->Pole(i, j);
      poles.emplace_back(p.X(), p.Y(), p.Z());
    }
  }
  OcctFit result{d2vdb::BSplineSurface(d2vdb::KnotVector(s->UDegree(), flatKnots(knotsU, multU)),
                                       d2vdb::KnotVector(s->VDegree(), flatKnots(knotsV, multV)),
                                       std::move(poles)),
                 s->UDegree(), s->VDegree(), elapsed.count()};
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  s->Bounds(u0, u1, v0, v1);
  for (int i = 0; i <= 10; ++i) {
    for (int j = 0; j <= 10; ++j) {
      const double u = u0 + (u1 - u0) * i / 10.0, v = v0 + (v1 - v0) * j / 10.0;
      const gp_Pnt p = s->Value(u, v);
      result.conversionError =
          std::max(result.conversionError,
                   (Eigen::Vector3d(p.X(), p.Y(), p.Z()) - result.surface.evaluate(u, v)).norm());
    }
  }
  const auto corner = [&](double u, double v, int i, int j) {
    const gp_Pnt p = s->Value(u, v);
    return (Eigen::Vector3d(p.X(), p.Y(), p.Z()) -
            gridSamples()[static_cast<std::size_t>(i * kGridV + j)])
        .norm();
  };
  result.cornerError =
      std::max({corner(u0, v0, 0, 0), corner(u1, v0, kGridU - 1, 0), corner(u0, v1, 0, kGridV - 1),
                corner(u1, v1, kGridU - 1, kGridV - 1)});
  return result;
}

/// OCCT's fit at tolerance 10^-exponent, run once per process for the net (single thread).
const OcctFit& occtNet(int exponent) {
  static std::map<int, OcctFit> fits;
  const auto found = fits.find(exponent);
  if (found != fits.end()) return found->second;
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
  return fits.emplace(exponent, occtFit(std::pow(10.0, -exponent))).first->second;
}

/// The d2vdb start: a clamped bicubic net of countU x countV control points at the Greville
/// abscissae of the patch on the torus of radii `major` and `minor` (same angles).
d2vdb::BSplineSurface startSurface(int countU, int countV, double major, double minor) {
  const auto greville = [](int count) {
    const std::vector<double> knots = d2vdb::KnotVector::clamped(3, count).values();
    std::vector<double> abscissae;
    for (int i = 0; i < count; ++i) {
      abscissae.push_back((knots[static_cast<std::size_t>(i + 1)] +
                           knots[static_cast<std::size_t>(i + 2)] +
                           knots[static_cast<std::size_t>(i + 3)]) /
                          3.0);
    }
    return abscissae;
  };
  const std::vector<double> s = greville(countU), t = greville(countV);
  std::vector<Eigen::Vector3d> points;
  for (const double si : s) {
    for (const double tj : t) {
      points.push_back(torusPoint(kStartA + (kEndA - kStartA) * si,
                                  kStartB + (kEndB - kStartB) * tj, major, minor));
    }
  }
  return d2vdb::BSplineSurface::clamped(3, 3, countU, countV, std::move(points));
}

/// The distance from each of `points` to `surface`: its nearest point found by SurfaceProjector,
/// started (as its hint) from the nearest of 101 x 101 samples of the surface, so that a folded
/// or overhanging fit cannot trap it in a far local minimum.
std::vector<double> distancesTo(const d2vdb::BSplineSurface& surface,
                                const std::vector<Eigen::Vector3d>& points) {
  const d2vdb::SurfaceProjector projector(surface);
  const std::vector<Eigen::Vector3d> samples = surface.sample(101, 101);
  std::vector<d2vdb::SurfaceFootpoint> hints(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    std::size_t nearest = 0;
    for (std::size_t m = 1; m < samples.size(); ++m) {
      if ((samples[m] - points[k]).squaredNorm() < (samples[nearest] - points[k]).squaredNorm()) {
        nearest = m;
      }
    }
    d2vdb::SurfaceFootpoint& hint = hints[k];
    hint.u = surface.domainU().at(static_cast<double>(nearest / 101) / 100.0);
    hint.v = surface.domainV().at(static_cast<double>(nearest % 101) / 100.0);
    hint.point = samples[nearest];
    hint.squaredDistance = (samples[nearest] - points[k]).squaredNorm();
    const std::vector<d2vdb::BezierPatch>& patches = projector.patches();
    for (std::size_t patch = 0; patch < patches.size(); ++patch) {
      const d2vdb::BezierPatch& piece = patches[patch];
      if (hint.u >= piece.intervalU.start && hint.u <= piece.intervalU.end &&
          hint.v >= piece.intervalV.start && hint.v <= piece.intervalV.end) {
        hint.patch = static_cast<int>(patch);
        break;
      }
    }
  }
  const std::vector<d2vdb::SurfaceFootpoint> found = projector.nearest(points, hints);
  std::vector<double> distances;
  for (std::size_t k = 0; k < points.size(); ++k) {
    distances.push_back(std::sqrt(std::min(found[k].squaredDistance, hints[k].squaredDistance)));
  }
  return distances;
}

/// The largest distance from patchPoints() to `surface`.
double coverage(const d2vdb::BSplineSurface& surface) {
  const std::vector<double> distances = distancesTo(surface, patchPoints());
  return *std::max_element(distances.begin(), distances.end());
}

/// RMS distance from gridSamples() to `surface` (what SDM II's data_rms measures).
double dataRms(const d2vdb::BSplineSurface& surface) {
  double sum = 0.0;
  for (const double d : distancesTo(surface, gridSamples())) sum += d * d;
  return std::sqrt(sum / static_cast<double>(gridSamples().size()));
}

/// The accuracy counters of the header comment.
void accuracyCounters(benchmark::State& state, const d2vdb::BSplineSurface& surface) {
  double largest = 0.0, sum = 0.0, largestAll = 0.0;
  int inside = 0;
  const std::vector<Eigen::Vector3d> points = surface.sample(201, 201);
  for (const Eigen::Vector3d& p : points) {
    const double d = torusDistance(p);
    largestAll = std::max(largestAll, d);
    const double a = angleA(p), b = angleB(p);
    if (a < kStartA || a > kEndA || b < kStartB || b > kEndB) continue;
    largest = std::max(largest, d);
    sum += d * d;
    ++inside;
  }
  state.counters["max_error_all"] = largestAll;
  state.counters["inside"] = static_cast<double>(inside) / static_cast<double>(points.size());
  state.counters["max_error"] = largest;
  state.counters["rms_error"] = std::sqrt(sum / std::max(inside, 1));
  state.counters["coverage"] = coverage(surface);
  // Edge midpoints: their torus angles against the patch's edges.
  const d2vdb::ParameterInterval du = surface.domainU(), dv = surface.domainV();
  const double um = 0.5 * (du.start + du.end), vm = 0.5 * (dv.start + dv.end);
  const auto gap = [](double angle, double edge) {
    return std::abs(std::remainder(angle - edge, 2 * kPi));
  };
  state.counters["edge_shift"] = std::max({gap(angleA(surface.evaluate(du.start, vm)), kStartA),
                                           gap(angleA(surface.evaluate(du.end, vm)), kEndA),
                                           gap(angleB(surface.evaluate(um, dv.start)), kStartB),
                                           gap(angleB(surface.evaluate(um, dv.end)), kEndB)});
}

void netCounters(benchmark::State& state, const d2vdb::BSplineSurface& surface) {
  state.counters["poles_u"] = surface.countU();
  state.counters["poles_v"] = surface.countV();
}

using d2vdb::bench::median;

/// BM_Occt/tol_exp: OCCT's fit alone, one thread.
void BM_Occt(benchmark::State& state) {
  const int exponent = static_cast<int>(state.range(0));
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
  std::vector<double> times;
  OcctFit fit = occtNet(exponent);
  for (auto _ : state) {
    fit = occtFit(std::pow(10.0, -exponent));
    state.SetIterationTime(fit.seconds);
    times.push_back(fit.seconds);
  }
  netCounters(state, fit.surface);
  accuracyCounters(state, fit.surface);
  state.counters["ms"] = 1e3 * median(times);
  state.counters["degrees"] = 10 * fit.degreeU + fit.degreeV;
  state.counters["conversion_error"] = fit.conversionError;
  state.counters["corner_error"] = fit.cornerError;
  state.counters["data_rms"] = dataRms(fit.surface);
}

/// The d2vdb benchmarks (arguments tol_exp, start, threads): each iteration times OCCT (one
/// thread) and then the d2vdb fit on `threads` threads, from startSurface() with radii 1.7 and 0.8
/// (start 0) or the torus's own 2 and 0.5 (start 1: the attainable accuracy, apart from the start).
template <typename Fit>
void pairedWithOcct(benchmark::State& state, Fit&& fit) {
  const int exponent = static_cast<int>(state.range(0));
  const bool exactStart = state.range(1) == 1;
  const std::size_t threads = static_cast<std::size_t>(state.range(2));
  const OcctFit& net = occtNet(exponent);
  const d2vdb::BSplineSurface initial =
      startSurface(net.surface.countU(), net.surface.countV(), exactStart ? kMajor : 1.7,
                   exactStart ? kMinor : 0.8);
  std::vector<double> occtTimes, times;
  std::optional<d2vdb::SurfaceFitResult> result;
  for (auto _ : state) {
    {
      const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      occtTimes.push_back(occtFit(std::pow(10.0, -exponent)).seconds);
    }
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const auto start = std::chrono::steady_clock::now();
    result.emplace(fit(initial));
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    state.SetIterationTime(elapsed.count());
    times.push_back(elapsed.count());
  }
  netCounters(state, result->surface);
  accuracyCounters(state, result->surface);
  state.counters["iterations"] = result->iterations();
  state.counters["converged"] = result->status == d2vdb::FitStatus::Converged ? 1.0 : 0.0;
  state.counters["data_rms"] = result->history.back().rmsDistance;
  state.counters["occt_ms"] = 1e3 * median(occtTimes);
  state.counters["ms"] = 1e3 * median(times);
  state.counters["ratio"] = median(times) / median(occtTimes);
  state.SetLabel(result->reason);
}

void BM_D2vdbPoints(benchmark::State& state) {
  pairedWithOcct(state, [](const d2vdb::BSplineSurface& initial) {
    return d2vdb::fitSurfaceToPoints(initial, gridSamples(), {});
  });
}

void BM_D2vdbField(benchmark::State& state) {
  torusField();  // built once, outside the timing
  pairedWithOcct(state, [](const d2vdb::BSplineSurface& initial) {
    return d2vdb::fitSurface(initial, torusField(), {});
  });
}

void BM_D2vdbPatch(benchmark::State& state) {
  static const ExactPatchTarget target;
  pairedWithOcct(state, [](const d2vdb::BSplineSurface& initial) {
    return d2vdb::fitSurface(initial, target, {});
  });
}

/// BM_D2vdbPointsToOcctRms/tol_exp: SDM II as BM_D2vdbPoints from the start of radii 1.7 and 0.8
/// on one thread, stopped when its data RMS reaches OCCT's at that tolerance
/// (SurfaceFitOptions::distanceTolerance; cap 1000 iterations): the time d2vdb needs to be as
/// close to the samples as OCCT. Counter reached = 1 when it got there.
void BM_D2vdbPointsToOcctRms(benchmark::State& state) {
  d2vdb::SurfaceFitOptions options;
  options.distanceTolerance = dataRms(occtNet(static_cast<int>(state.range(0))).surface);
  options.maxIterations = 1000;
  pairedWithOcct(state, [&](const d2vdb::BSplineSurface& initial) {
    return d2vdb::fitSurfaceToPoints(initial, gridSamples(), options);
  });
  state.counters["occt_data_rms"] = options.distanceTolerance;
  state.counters["reached"] = state.counters["data_rms"] <= options.distanceTolerance ? 1.0 : 0.0;
}

/// The tolerances 10^-k.
void tolerances(benchmark::internal::Benchmark* b) {
  for (int exponent = 2; exponent <= 6; ++exponent) b->Args({exponent});
}
/// The tolerances, the start of radii 1.7 and 0.8 on 1 and 2 threads, the exact start on 1.
void tolerancesStartsThreads(benchmark::internal::Benchmark* b) {
  for (int exponent = 2; exponent <= 6; ++exponent) {
    b->Args({exponent, 0, 1});
    b->Args({exponent, 0, 2});
    b->Args({exponent, 1, 1});
  }
}

BENCHMARK(BM_Occt)
    ->ArgNames({"tol_exp"})
    ->Apply(tolerances)
    ->Iterations(5)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();
BENCHMARK(BM_D2vdbPoints)
    ->ArgNames({"tol_exp", "start", "threads"})
    ->Apply(tolerancesStartsThreads)
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();
BENCHMARK(BM_D2vdbField)
    ->ArgNames({"tol_exp", "start", "threads"})
    ->Apply(tolerancesStartsThreads)
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

BENCHMARK(BM_D2vdbPatch)
    ->ArgNames({"tol_exp", "start", "threads"})
    ->Apply(tolerancesStartsThreads)
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

BENCHMARK(BM_D2vdbPointsToOcctRms)
    ->ArgNames({"tol_exp", "start", "threads"})
    ->Apply([](benchmark::internal::Benchmark* b) {
      for (int exponent = 2; exponent <= 6; ++exponent) b->Args({exponent, 0, 1});
    })
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

}  // namespace

BENCHMARK_MAIN();
