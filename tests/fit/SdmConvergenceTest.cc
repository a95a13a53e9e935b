// SDM II with default options on generated point clouds of known curves (closed and open, 2D and
// 3D; noisy, thick, non-uniformly sampled and clean): it must converge (the geometric test, not
// the iteration cap) within 30 iterations, and the fitted curve must come as close to the clean
// curve as the noise and the control net allow: RMS distance <= 1.1 sqrt(f_noise^2 +
// f_approx^2) with f_noise = sigma sqrt(2 m / N) and f_approx the RMS distance the same control
// net reaches on clean dense samples of the curve (measured here).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "FitTestSupport.h"
#include "d2vdb/fit/InitialCurve.h"
#include "d2vdb/fit/PointCloudFitter.h"

namespace d2vdb {
namespace {

using test::GeneratedCloud;
using test::ParametricCurve;
using test::Sampling;

constexpr int kCloudPoints = 3000;
constexpr int kDensePoints = 2000;
constexpr int kIterationGoal = 30;
constexpr unsigned kSeeds[] = {1, 2, 3};

struct CurveCase {
  std::string name;
  ParametricCurve curve;
  int dimension = 2;
  double size = 1.0;  // largest extent of the curve
  int controlPoints = 16;
  /// Scales f_noise^2 in the accuracy bound: 1 in 2D; in 3D a control point has three
  /// coordinates and the noise reaches a least-squares fit through about 3 m of its parameters
  /// against the 2 m that f_noise = sigma sqrt(2 m / N) counts, so 1.5 there.
  double noiseFactor = 1.0;
};

CurveCase closedPlanar() {
  return {"closed 2D loop", test::threeLobedLoop(), 2, 2.4, 16, 1.0};
}
CurveCase openPlanar() {
  return {"open 2D wave", test::openWave(), 2, 2.0, 12, 1.0};
}
CurveCase closedSpace() {
  return {"closed 3D loop", test::wavySpaceLoop(), 3, 2.5, 20, 1.5};
}
CurveCase openSpace() {
  return {"open 3D helix", test::helixCurve(1.0, 0.25, 1.5), 3, 2.0, 16, 1.5};
}

const char* samplingName(Sampling sampling) {
  switch (sampling) {
    case Sampling::Noisy:
      return "noisy";
    case Sampling::Thick:
      return "thick";
    case Sampling::NonUniform:
      return "non-uniform";
    case Sampling::Clean:
      return "clean";
  }
  return "?";
}

/// The initial curve a user would start from: an ellipse around the cloud for a closed curve (as
/// `fit-curve --init ellipse`), a least-squares curve through a rough ordered sketch of the curve
/// (30 points off it by up to 2 % of its size) for an open one.
BSplineCurve initialCurve(const CurveCase& c, const GeneratedCloud& cloud) {
  if (c.curve.periodic) {
    return initialCurveAround(cloud.points, InitialShape::Ellipse, 3, c.controlPoints, c.dimension,
                              1.2);
  }
  std::vector<Eigen::Vector3d> sketch = test::samplePoints(c.curve, 30);
  for (std::size_t i = 0; i < sketch.size(); ++i) {
    sketch[i] += 0.02 * c.size *
                 Eigen::Vector3d(std::sin(1.7 * i), std::cos(2.3 * i),
                                 c.dimension == 3 ? std::sin(0.7 * i) : 0.0);
  }
  return fitPolylineLeastSquares(sketch, false, 3, c.controlPoints, c.dimension);
}

struct Fit {
  CurveFitResult result;
  double rms = 0.0;       // to the clean curve (without the overhang past open ends)
  double overhang = 0.0;  // fraction of the fitted curve past an open curve's ends
};

Fit fitCloud(const CurveCase& c, const GeneratedCloud& cloud, const CurveFitOptions& options = {}) {
  Fit fit{fitCurveToPoints(initialCurve(c, cloud), cloud.points, options), 0.0, 0.0};
  fit.rms = test::splineToCurveInterior(fit.result.curve, c.curve, 1000, &fit.overhang);
  return fit;
}

/// f_approx: the RMS distance to the curve that the control net reaches on clean dense samples
/// with default options (computed once per curve).
double approximationError(const CurveCase& c) {
  static std::vector<std::pair<std::string, double>> cache;
  for (const auto& [name, value] : cache) {
    if (name == c.name) return value;
  }
  const GeneratedCloud dense =
      test::generateCloud(c.curve, c.dimension, Sampling::Clean, kDensePoints, c.size, 1);
  cache.emplace_back(c.name, fitCloud(c, dense).rms);
  return cache.back().second;
}

/// The clean dense sampling: converged, and f_approx is a fair reference (a fit run much longer
/// with a 100 times tighter geometric tolerance gets no closer).
void checkClean(const CurveCase& c) {
  const GeneratedCloud dense =
      test::generateCloud(c.curve, c.dimension, Sampling::Clean, kDensePoints, c.size, 1);
  const Fit clean = fitCloud(c, dense);
  CurveFitOptions tight;
  tight.moveTolerance = 1e-3;
  tight.maxIterations = 200;
  const Fit tighter = fitCloud(c, dense, tight);
  std::printf(
      "%s clean (%d points): %d iterations, %s, RMS to the curve %.4g (%d iterations "
      "with a 100x tighter tolerance: %.4g)\n",
      c.name.c_str(), kDensePoints, clean.result.iterations(), fitStatusName(clean.result.status),
      clean.rms, tighter.result.iterations(), tighter.rms);
  EXPECT_EQ(clean.result.status, FitStatus::Converged) << c.name << ": " << clean.result.reason;
  EXPECT_LE(clean.result.iterations(), kIterationGoal) << c.name;
  EXPECT_LE(clean.rms, 1.02 * tighter.rms) << c.name;
}

/// The noisy, thick or non-uniform sampling, three random clouds: every fit converges
/// within kIterationGoal iterations, without folding or chasing the noise, and the RMS distance to
/// the clean curve over the three clouds is within 1.1 sqrt(noiseFactor f_noise^2 + f_approx^2).
void checkNoisy(const CurveCase& c, Sampling sampling) {
  const double fApprox = approximationError(c);
  {
    double sumSquares = 0.0;
    double bound = 0.0;
    for (const unsigned seed : kSeeds) {
      const GeneratedCloud cloud =
          test::generateCloud(c.curve, c.dimension, sampling, kCloudPoints, c.size, seed);
      const Fit fit = fitCloud(c, cloud);
      const double fNoise = cloud.sigma * std::sqrt(2.0 * c.controlPoints / kCloudPoints);
      bound = 1.1 * std::sqrt(c.noiseFactor * fNoise * fNoise + fApprox * fApprox);
      sumSquares += fit.rms * fit.rms;
      std::printf(
          "%s %s (seed %u): %d iterations, %s; RMS to the clean curve %.4g (f_noise %.4g, "
          "f_approx %.4g), overhang %.3f, final smoothness %.3g\n",
          c.name.c_str(), samplingName(sampling), seed, fit.result.iterations(),
          fitStatusName(fit.result.status), fit.rms, fNoise, fApprox, fit.overhang,
          fit.result.history.back().smoothness);
      EXPECT_EQ(fit.result.status, FitStatus::Converged)
          << c.name << " " << samplingName(sampling) << ": " << fit.result.reason;
      EXPECT_LE(fit.result.iterations(), kIterationGoal) << c.name << " " << samplingName(sampling);
      // The data RMS is the noise level (the fit neither chases the noise nor folds into a thick
      // band): within 5 % of sigma times the number of normal directions' root.
      const double expectedRms = cloud.sigma * std::sqrt(c.dimension - 1.0);
      EXPECT_NEAR(fit.result.history.back().rmsDistance, expectedRms, 0.05 * expectedRms)
          << c.name << " " << samplingName(sampling);
      EXPECT_LT(fit.overhang, 0.03) << c.name << " " << samplingName(sampling);
    }
    const double rms = std::sqrt(sumSquares / std::size(kSeeds));
    std::printf("%s %s: RMS to the clean curve over the clouds %.4g, bound %.4g\n", c.name.c_str(),
                samplingName(sampling), rms, bound);
    EXPECT_LE(rms, bound) << c.name << " " << samplingName(sampling);
  }
}

// One test per curve and sampling (each a few fits of 3000 points).
TEST(SdmConvergence, ClosedPlanarCurveNoisy) {
  checkNoisy(closedPlanar(), Sampling::Noisy);
}
TEST(SdmConvergence, ClosedPlanarCurveThick) {
  checkNoisy(closedPlanar(), Sampling::Thick);
}
TEST(SdmConvergence, ClosedPlanarCurveNonUniform) {
  checkNoisy(closedPlanar(), Sampling::NonUniform);
}
TEST(SdmConvergence, ClosedPlanarCurveClean) {
  checkClean(closedPlanar());
}
TEST(SdmConvergence, OpenPlanarCurveNoisy) {
  checkNoisy(openPlanar(), Sampling::Noisy);
}
TEST(SdmConvergence, OpenPlanarCurveThick) {
  checkNoisy(openPlanar(), Sampling::Thick);
}
TEST(SdmConvergence, OpenPlanarCurveNonUniform) {
  checkNoisy(openPlanar(), Sampling::NonUniform);
}
TEST(SdmConvergence, ClosedSpaceCurveNoisy) {
  checkNoisy(closedSpace(), Sampling::Noisy);
}
TEST(SdmConvergence, ClosedSpaceCurveThick) {
  checkNoisy(closedSpace(), Sampling::Thick);
}
TEST(SdmConvergence, ClosedSpaceCurveNonUniform) {
  checkNoisy(closedSpace(), Sampling::NonUniform);
}
TEST(SdmConvergence, ClosedSpaceCurveClean) {
  checkClean(closedSpace());
}
TEST(SdmConvergence, OpenSpaceCurveNoisy) {
  checkNoisy(openSpace(), Sampling::Noisy);
}
TEST(SdmConvergence, OpenSpaceCurveThick) {
  checkNoisy(openSpace(), Sampling::Thick);
}
TEST(SdmConvergence, OpenSpaceCurveNonUniform) {
  checkNoisy(openSpace(), Sampling::NonUniform);
}

TEST(SdmConvergence, OpenPlanarCurveClean) {
  checkClean(openPlanar());
}
TEST(SdmConvergence, OpenSpaceCurveClean) {
  checkClean(openSpace());
}

TEST(SdmConvergence, ExactSecondOrderTermsRemoveTheSlidingDrift) {
  // The plain SDM II terms (Wang, Pottmann and Liu 2006) leave the curve sliding along itself
  // on a noisy cloud; with the exact second-order terms the same fit converges like Newton's
  // method to the same curve.
  const CurveCase c = closedPlanar();
  const GeneratedCloud cloud =
      test::generateCloud(c.curve, c.dimension, Sampling::Noisy, kCloudPoints, c.size, 1);
  const Fit exact = fitCloud(c, cloud);
  CurveFitOptions plain;
  plain.exactSecondOrder = false;
  plain.maxIterations = 4 * exact.result.iterations();
  const Fit drifting = fitCloud(c, cloud, plain);
  std::printf("exact second order: %d iterations (%s); plain SDM: %d iterations (%s)\n",
              exact.result.iterations(), fitStatusName(exact.result.status),
              drifting.result.iterations(), fitStatusName(drifting.result.status));
  ASSERT_EQ(exact.result.status, FitStatus::Converged) << exact.result.reason;
  EXPECT_EQ(drifting.result.status, FitStatus::IterationCap) << drifting.result.reason;
  // Both reach the same curve to within a tenth of the noise floor (the plain fit still moving).
  const double fNoise = cloud.sigma * std::sqrt(2.0 * c.controlPoints / kCloudPoints);
  EXPECT_NEAR(exact.rms, drifting.rms, 0.1 * fNoise);
}

TEST(SdmConvergence, FootpointCorrectionStraightensTheReparametrizationValley) {
  // Clean dense samples of an open helix: once the curve lies on the data, what is left is to
  // slide the control points along the curve (its parametrisation), a long curved valley of the
  // squared distance that Newton's steps alone follow in many short steps. Correcting every step
  // by the least-squares fit for the footpoint parameters it reached gets to the same curve in a
  // fraction of the iterations.
  const CurveCase c = openSpace();
  const GeneratedCloud dense =
      test::generateCloud(c.curve, c.dimension, Sampling::Clean, kDensePoints, c.size, 1);
  const Fit corrected = fitCloud(c, dense);
  CurveFitOptions uncorrectedOptions;
  uncorrectedOptions.footpointCorrection = false;
  const Fit uncorrected = fitCloud(c, dense, uncorrectedOptions);
  std::printf(
      "footpoint correction: %d iterations, RMS to the curve %.4g; without: %d iterations, %.4g\n",
      corrected.result.iterations(), corrected.rms, uncorrected.result.iterations(),
      uncorrected.rms);
  ASSERT_EQ(corrected.result.status, FitStatus::Converged) << corrected.result.reason;
  ASSERT_EQ(uncorrected.result.status, FitStatus::Converged) << uncorrected.result.reason;
  EXPECT_LT(2 * corrected.result.iterations(), uncorrected.result.iterations());
  EXPECT_NEAR(corrected.rms, uncorrected.rms, 0.02 * uncorrected.rms);
}

TEST(SdmConvergence, TheCapMessageNamesTheCapTheUserSet) {
  const CurveCase c = closedPlanar();
  const GeneratedCloud cloud =
      test::generateCloud(c.curve, c.dimension, Sampling::NonUniform, kCloudPoints, c.size, 1);
  CurveFitOptions options;
  options.maxIterations = 3;
  const Fit fit = fitCloud(c, cloud, options);
  EXPECT_EQ(fit.result.status, FitStatus::IterationCap);
  EXPECT_EQ(fit.result.iterations(), 3);
  EXPECT_NE(fit.result.reason.find("iteration cap of 3 "), std::string::npos) << fit.result.reason;
}

}  // namespace
}  // namespace d2vdb
