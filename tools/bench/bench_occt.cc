// d2vdb's surface fitter beside OpenCASCADE's GeomAPI_PointsToBSplineSurface (OCCT, built only
// where its Debian packages are installed; tools/bench/CMakeLists.txt). The shape is an open patch
// of the torus R = 2, r = 0.5 about the z axis,
//   T(a, b) = ((R + r cos b) cos a, (R + r cos b) sin a, r sin b),  a in [0, pi/2], b in [0, pi]
// (a quarter of the major circle times the upper half of the tube: it runs from the outer equator
// over the top to the inner equator, so it holds both elliptic and hyperbolic points).
//  - BM_Occt/tol_exp: GeomAPI_PointsToBSplineSurface on the kGridU x kGridV grid of exact samples
//    T(a_i, b_j) (uniform in a and b; TColgp_Array2OfPnt), degree 3 exactly (DegMin = DegMax =
//    3), C2, Tol3D = 10^-tol_exp, default (chord-length) parametrisation. OCCT chooses its knots
//    from the tolerance; counters poles_u x poles_v give the control net it produced.
//  - BM_D2vdbPoints/tol_exp/threads: d2vdb SDM II (fitSurfaceToPoints, default options) on the
//    same grid of samples as a point cloud, bicubic open x open with the net OCCT produced at that
//    tolerance (clamped uniform knots), from the start below.
//  - BM_D2vdbField/tol_exp/threads: d2vdb SDM I (fitSurface, default options) on the torus's
//    level set (primitiveLevelSet, voxel 0.01, through the approximant field), same net and start.
//    The field holds the whole torus, so nothing holds the patch's edges to the patch: the fit
//    settles where its sensors and the smoothing put them (see coverage and edge_shift).
// The d2vdb start: the control net at the Greville abscissae of T with the wrong radii 1.7 and 0.8
// over the same angles (the torus start, here open).
//
// Each d2vdb benchmark iteration times the OCCT fit (one thread) right before the d2vdb fit, so
// both see the same machine load; counters occt_ms and ms are medians, ratio = ms / occt_ms. Time
// is wall time (manual). Accuracy, for every surface alike (OCCT's converted exactly to a d2vdb
// surface, checked by evaluating both):
//  - max_error, rms_error: exact distance |sqrt((rho - R)^2 + z^2) - r| from the fitted surface to
//    the analytic torus at 201 x 201 points of the surface's whole parameter domain (edges
//    included);
//  - coverage: the largest distance from 101 x 101 exact points of the patch (edges included) to
//    the fitted surface (SurfaceProjector: exact nearest point, edges included), so a fit that is
//    close to the torus but does not span the patch shows;
//  - edge_shift (field fits): the largest angle, in radians of the tube or major circle, by which
//    the fitted surface's four edge midpoints lie away from the patch's edges.
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <benchmark/benchmark.h>
#include <gp_Pnt.hxx>
#include <tbb/global_control.h>

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

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

/// The torus's level set, voxel 0.01, as an approximant field (built once).
const d2vdb::ApproximantField& torusField() {
  static const d2vdb::ApproximantField field = [] {
    d2vdb::PrimitiveLevelSetOptions options;
    options.voxelSize = 0.01;
    options.halfWidth = 3;
    const d2vdb::Torus torus(Eigen::Vector3d::Zero(), kMajor, kMinor);
    return d2vdb::ApproximantField::fromLevelSet(d2vdb::primitiveLevelSet(torus, options));
  }();
  return field;
}

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
  result.cornerError = std::max({corner(u0, v0, 0, 0), corner(u1, v0, kGridU - 1, 0),
                                 corner(u0, v1, 0, kGridV - 1),
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
/// abscissae of the patch on the torus of radii 1.7 and 0.8.
d2vdb::BSplineSurface startSurface(int countU, int countV) {
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
                                  kStartB + (kEndB - kStartB) * tj, 1.7, 0.8));
    }
  }
  return d2vdb::BSplineSurface::clamped(3, 3, countU, countV, std::move(points));
}

/// Torus angles (a, b) of the point of the torus nearest to p: a around the axis, b around the
/// tube (b in (-pi, pi], 0 on the outer equator).
double angleA(const Eigen::Vector3d& p) { return std::atan2(p.y(), p.x()); }
double angleB(const Eigen::Vector3d& p) {
  return std::atan2(p.z(), std::hypot(p.x(), p.y()) - kMajor);
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
  const d2vdb::SurfaceProjector projector(surface);
  double coverage = 0.0;
  for (const d2vdb::SurfaceFootpoint& f : projector.nearest(patchPoints())) {
    coverage = std::max(coverage, std::sqrt(f.squaredDistance));
  }
  state.counters["coverage"] = coverage;
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

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

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
}

/// The d2vdb benchmarks: each iteration times OCCT (one thread) and then the d2vdb fit on
/// `threads` threads.
template <typename Fit>
void pairedWithOcct(benchmark::State& state, Fit&& fit) {
  const int exponent = static_cast<int>(state.range(0));
  const std::size_t threads = static_cast<std::size_t>(state.range(1));
  const OcctFit& net = occtNet(exponent);
  const d2vdb::BSplineSurface initial = startSurface(net.surface.countU(), net.surface.countV());
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

/// The tolerances 10^-k.
void tolerances(benchmark::internal::Benchmark* b) {
  for (int exponent = 2; exponent <= 6; ++exponent) b->Args({exponent});
}
void tolerancesAndThreads(benchmark::internal::Benchmark* b) {
  for (int exponent = 2; exponent <= 6; ++exponent) {
    for (int threads = 1; threads <= 2; ++threads) b->Args({exponent, threads});
  }
}

BENCHMARK(BM_Occt)
    ->ArgNames({"tol_exp"})
    ->Apply(tolerances)
    ->Iterations(5)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();
BENCHMARK(BM_D2vdbPoints)
    ->ArgNames({"tol_exp", "threads"})
    ->Apply(tolerancesAndThreads)
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();
BENCHMARK(BM_D2vdbField)
    ->ArgNames({"tol_exp", "threads"})
    ->Apply(tolerancesAndThreads)
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();

}  // namespace

BENCHMARK_MAIN();
