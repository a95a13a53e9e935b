#include "d2vdb/spline/BSplineCurve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"
#include "d2vdb/spline/BasisFunctions.h"
#include "spline/SplineTestSupport.h"

namespace {

using d2vdb::BSplineCurve;
using d2vdb::InputError;
using d2vdb::KnotVector;
using Eigen::Vector3d;

BSplineCurve randomCurve(std::mt19937& rng, int degree, bool clamped, bool planar = false) {
  KnotVector knots = d2vdb::test::randomKnotVector(rng, degree, clamped);
  const int count = knots.basisFunctionCount();
  return BSplineCurve(std::move(knots), d2vdb::test::randomPoints(rng, count, planar),
                      planar ? 2 : 3);
}

// Parameters spread over the domain, including both ends and every breakpoint.
std::vector<double> testParameters(std::mt19937& rng, const d2vdb::ParameterInterval& domain,
                                   const KnotVector& knots, int randomCount = 200) {
  std::vector<double> parameters = knots.breakpoints();
  for (int i = 0; i < randomCount; ++i) {
    parameters.push_back(d2vdb::test::randomParameter(rng, domain.start, domain.end));
  }
  return parameters;
}

// Expects `action` to throw InputError with `fragment` in its message.
template <typename Action>
void expectInputError(Action action, const std::string& fragment) {
  try {
    action();
    FAIL() << "expected InputError containing '" << fragment << "'";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(fragment), std::string::npos) << error.what();
  }
}

TEST(BSplineCurve, ReproducesAPolynomialFromItsBlossomExactly) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 40; ++trial) {
    const int degree = 1 + trial % 5;
    const KnotVector knots = d2vdb::test::randomKnotVector(rng, degree, trial % 2 == 0);
    // A random vector polynomial f(t) = sum_k a_k t^k of the spline's degree.
    const std::vector<Vector3d> a = d2vdb::test::randomPoints(rng, degree + 1);
    // Marsden / blossoming: P_i = f(t_{i+1}, ..., t_{i+p}) = sum_k a_k e_k(...) / C(p, k).
    std::vector<Vector3d> points;
    for (int i = 0; i < knots.basisFunctionCount(); ++i) {
      std::vector<double> arguments;
      for (int r = 1; r <= degree; ++r) arguments.push_back(knots[i + r]);
      Vector3d point = Vector3d::Zero();
      for (int k = 0; k <= degree; ++k) {
        point += a[static_cast<std::size_t>(k)] * d2vdb::test::monomialBlossom(arguments, k);
      }
      points.push_back(point);
    }
    const BSplineCurve curve(knots, points);
    // Derivative coefficients of f: f' = sum k a_k t^(k-1), f'' likewise.
    std::vector<Vector3d> first;
    std::vector<Vector3d> second;
    for (int k = 1; k <= degree; ++k) first.push_back(k * a[static_cast<std::size_t>(k)]);
    for (int k = 2; k <= degree; ++k)
      second.push_back(k * (k - 1) * a[static_cast<std::size_t>(k)]);
    for (double t : testParameters(rng, curve.domain(), knots)) {
      const d2vdb::CurveDerivatives d = curve.derivatives(t);
      EXPECT_LT((curve.evaluate(t) - d2vdb::test::polynomialValue(a, t)).norm(), 1e-12);
      EXPECT_LT((d.point - d2vdb::test::polynomialValue(a, t)).norm(), 1e-12);
      EXPECT_LT((d.first - d2vdb::test::polynomialValue(first, t)).norm(), 1e-10);
      EXPECT_LT((d.second - d2vdb::test::polynomialValue(second, t)).norm(), 1e-9);
    }
  }
}

TEST(BSplineCurve, DerivativesMatchCentralDifferences) {
  std::mt19937 rng(32);
  for (int trial = 0; trial < 60; ++trial) {
    const int degree = 2 + trial % 4;
    const BSplineCurve curve = randomCurve(rng, degree, trial % 2 == 0);
    const auto domain = curve.domain();
    const double h = 1e-6;
    int checked = 0;
    while (checked < 20) {
      const double t = d2vdb::test::randomParameter(rng, domain.start + h, domain.end - h);
      // Central differences need a polynomial piece around t: stay 2h away from every knot.
      bool nearKnot = false;
      for (double knot : curve.knots().values()) nearKnot = nearKnot || std::abs(t - knot) < 2 * h;
      if (nearKnot) continue;
      ++checked;
      const d2vdb::CurveDerivatives d = curve.derivatives(t);
      const Vector3d firstDifference = (curve.evaluate(t + h) - curve.evaluate(t - h)) / (2 * h);
      const Vector3d secondDifference =
          (curve.derivatives(t + h).first - curve.derivatives(t - h).first) / (2 * h);
      EXPECT_LT((d.first - firstDifference).norm(), 1e-6 * (1.0 + d.first.norm()));
      EXPECT_LT((d.second - secondDifference).norm(), 1e-5 * (1.0 + d.second.norm()));
      EXPECT_EQ(curve.derivative(t, 0), d.point);
      EXPECT_LT((curve.derivative(t, 1) - d.first).norm(), 1e-12 * (1.0 + d.first.norm()));
      EXPECT_LT((curve.derivative(t, 2) - d.second).norm(), 1e-12 * (1.0 + d.second.norm()));
      EXPECT_EQ(curve.derivative(t, degree + 1), Vector3d::Zero());
    }
  }
}

TEST(BSplineCurve, BasisAndControlPointIndexReproduceEvaluation) {
  std::mt19937 rng(33);
  for (const bool closed : {false, true}) {
    const BSplineCurve curve = closed ? BSplineCurve::closed(3, d2vdb::test::randomPoints(rng, 7))
                                      : randomCurve(rng, 3, false);
    for (int k = 0; k < 50; ++k) {
      const double t = d2vdb::test::randomParameter(rng, curve.domain().start, curve.domain().end);
      const int span = curve.knots().findSpan(t);
      const d2vdb::BasisValues basis = d2vdb::basisValues(curve.knots(), span, t);
      Vector3d point = Vector3d::Zero();
      for (int j = 0; j <= curve.degree(); ++j) {
        point += basis[j] * curve.controlPoints()[static_cast<std::size_t>(
                                curve.controlPointIndex(span - curve.degree() + j))];
      }
      EXPECT_LT((point - curve.evaluate(t)).norm(), 1e-14);
    }
  }
}

TEST(BSplineCurve, KnotInsertionLeavesTheCurveUnchanged) {
  std::mt19937 rng(34);
  for (int trial = 0; trial < 60; ++trial) {
    const int degree = 1 + trial % 5;
    const BSplineCurve original = randomCurve(rng, degree, trial % 2 == 0);
    const auto domain = original.domain();
    // A new knot, once; an existing interior breakpoint (if any) up to full multiplicity p.
    BSplineCurve once = original;
    const double t = d2vdb::test::randomParameter(rng, domain.start, domain.end);
    once.insertKnot(t);
    EXPECT_EQ(once.knots().size(), original.knots().size() + 1);
    EXPECT_EQ(once.controlPointCount(), original.controlPointCount() + 1);
    EXPECT_EQ(once.knots().multiplicity(t), original.knots().multiplicity(t) + 1);

    BSplineCurve full = original;
    const std::vector<double> breaks = original.knots().breakpoints();
    const double existing = breaks.size() > 2 ? breaks[1] : domain.at(0.5);
    const int missing = degree - original.knots().multiplicity(existing);
    if (missing > 0) full.insertKnot(existing, missing);
    EXPECT_EQ(full.knots().multiplicity(existing), degree);
    // Full multiplicity p interpolates a control point there.
    const int span = full.knots().findSpan(existing);
    EXPECT_LT(
        (full.evaluate(existing) - full.controlPoints()[static_cast<std::size_t>(span - degree)])
            .norm(),
        1e-12);
    EXPECT_THROW(full.insertKnot(existing), InputError);

    for (double s : testParameters(rng, domain, original.knots())) {
      const Vector3d expected = original.evaluate(s);
      EXPECT_LT((once.evaluate(s) - expected).norm(), 1e-12);
      EXPECT_LT((full.evaluate(s) - expected).norm(), 1e-12);
    }
  }
}

TEST(BSplineCurve, KnotInsertionAtUnclampedEndsClampsTheCurve) {
  std::mt19937 rng(35);
  const BSplineCurve original = randomCurve(rng, 3, false);
  BSplineCurve clamped = original;
  const auto domain = original.domain();
  clamped.insertKnot(domain.start, 3);
  clamped.insertKnot(domain.end, 3);
  EXPECT_EQ(clamped.knots().multiplicity(domain.start), 4);
  EXPECT_EQ(clamped.knots().multiplicity(domain.end), 4);
  EXPECT_EQ(clamped.domain().start, domain.start);
  EXPECT_EQ(clamped.domain().end, domain.end);
  for (double s : testParameters(rng, domain, original.knots())) {
    EXPECT_LT((clamped.evaluate(s) - original.evaluate(s)).norm(), 1e-12);
  }
  // Clamped: the end points are control points.
  const auto& points = clamped.controlPoints();
  EXPECT_LT((clamped.evaluate(domain.start) - points[3]).norm(), 1e-12);
  EXPECT_LT((clamped.evaluate(domain.end) - points[points.size() - 4]).norm(), 1e-12);
  expectInputError([&] { clamped.insertKnot(domain.end); }, "at most 4");
  expectInputError([&] { clamped.insertKnot(domain.end + 1.0); }, "outside the domain");
  expectInputError([&] { clamped.insertKnot(domain.at(0.5), 0); }, "at least 1");
}

TEST(BSplineCurve, BezierExtractionReproducesTheCurve) {
  std::mt19937 rng(36);
  for (int trial = 0; trial < 60; ++trial) {
    const int degree = 1 + trial % 5;
    const BSplineCurve curve = randomCurve(rng, degree, trial % 2 == 0);
    const std::vector<d2vdb::BezierSegment> segments = curve.toBezierSegments();
    const std::vector<double> breaks = curve.knots().breakpoints();
    ASSERT_EQ(segments.size(), breaks.size() - 1);
    for (std::size_t i = 0; i < segments.size(); ++i) {
      const d2vdb::BezierSegment& segment = segments[i];
      EXPECT_EQ(segment.interval.start, breaks[i]);
      EXPECT_EQ(segment.interval.end, breaks[i + 1]);
      EXPECT_EQ(segment.curve.degree(), degree);
      for (int k = 0; k <= 20; ++k) {
        const double s = k / 20.0;
        EXPECT_LT((segment.curve.evaluate(s) - curve.evaluate(segment.interval.at(s))).norm(),
                  1e-12);
      }
      // The derivative with respect to s is the interval length times C'.
      const double s = 0.3;
      EXPECT_LT((segment.curve.derivative().evaluate(s) -
                 segment.interval.length() * curve.derivatives(segment.interval.at(s)).first)
                    .norm(),
                1e-10 * (1.0 + segment.curve.derivative().evaluate(s).norm()));
    }
  }
  // A clamped curve without interior knots is a single Bézier curve with the same control points.
  const std::vector<Vector3d> points = d2vdb::test::randomPoints(rng, 5);
  const std::vector<d2vdb::BezierSegment> single =
      BSplineCurve::clamped(4, points).toBezierSegments();
  ASSERT_EQ(single.size(), 1u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_LT((single[0].curve.controlPoint(i) - points[static_cast<std::size_t>(i)]).norm(),
              1e-15);
  }
}

TEST(BSplineCurve, ClosedCurvesArePeriodicAndSmoothAcrossTheSeam) {
  std::mt19937 rng(37);
  for (int degree = 1; degree <= 6; ++degree) {
    const int count = degree + 1 + degree % 3;
    const BSplineCurve curve =
        BSplineCurve::closed(degree, d2vdb::test::randomPoints(rng, count), 3, {0.5, 2.0});
    EXPECT_TRUE(curve.isClosed());
    EXPECT_EQ(curve.controlPointCount(), count);
    EXPECT_EQ(curve.knots().size(), count + 2 * degree + 1);
    const auto domain = curve.domain();
    const double period = domain.length();
    // Periodic in the parameter.
    for (int k = 0; k < 30; ++k) {
      const double t = d2vdb::test::randomParameter(rng, domain.start, domain.end);
      EXPECT_LT((curve.evaluate(t + period) - curve.evaluate(t)).norm(), 1e-12);
      EXPECT_LT((curve.evaluate(t - 3 * period) - curve.evaluate(t)).norm(), 1e-12);
    }
    // The open representation's last piece, evaluated at the domain end, meets the first piece
    // at the domain start in value and derivatives up to order p - 1 (C^(p-1) seam).
    const BSplineCurve open = curve.openRepresentation();
    EXPECT_FALSE(open.isClosed());
    for (int order = 0; order < degree; ++order) {
      const Vector3d atEnd = open.derivative(domain.end, order);
      const Vector3d atStart = curve.derivative(domain.start, order);
      EXPECT_LT((atEnd - atStart).norm(), 1e-10 * (1.0 + atStart.norm())) << "order " << order;
    }
    // Closed and open representations are the same curve.
    for (int k = 0; k <= 40; ++k) {
      const double t = domain.at(k / 40.0);
      EXPECT_LT((open.evaluate(t) - curve.evaluate(t)).norm(), 1e-13);
    }
    const std::vector<Vector3d> samples = curve.sample(17);
    ASSERT_EQ(samples.size(), 17u);
    EXPECT_LT((samples.front() - samples.back()).norm(), 1e-13);
  }
}

TEST(BSplineCurve, ClosedUniformCubicOfASquareIsSymmetric) {
  // Control points of a square: the closed uniform cubic has the square's symmetry, with the curve
  // point at each knot being (P_{i-1} + 4 P_i + P_{i+1}) / 6.
  const std::vector<Vector3d> square{{1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}};
  const BSplineCurve curve = BSplineCurve::closed(3, square, 2, {0.0, 4.0});
  EXPECT_EQ(curve.dimension(), 2);
  for (int i = 0; i < 4; ++i) {
    // Knot t_{3+i} = i is where basis functions i, i+1, i+2 meet (points P_i, P_{i+1}, P_{i+2}).
    const Vector3d expected =
        (square[static_cast<std::size_t>(i)] + 4.0 * square[static_cast<std::size_t>((i + 1) % 4)] +
         square[static_cast<std::size_t>((i + 2) % 4)]) /
        6.0;
    EXPECT_LT((curve.evaluate(i) - expected).norm(), 1e-14) << i;
  }
}

TEST(BSplineCurve, ClosedCurveKnotInsertionAndExtractionKeepTheCurve) {
  std::mt19937 rng(38);
  const BSplineCurve closed = BSplineCurve::closed(3, d2vdb::test::randomPoints(rng, 6));
  BSplineCurve refined = closed;
  refined.insertKnot(0.3, 2);
  EXPECT_FALSE(refined.isClosed());
  EXPECT_EQ(refined.controlPointCount(), 6 + 3 + 2);
  const std::vector<d2vdb::BezierSegment> segments = closed.toBezierSegments();
  EXPECT_EQ(segments.size(), 6u);
  for (int k = 0; k <= 100; ++k) {
    const double t = k / 100.0;
    EXPECT_LT((refined.evaluate(t) - closed.evaluate(t)).norm(), 1e-12);
  }
  for (const d2vdb::BezierSegment& segment : segments) {
    for (int k = 0; k <= 10; ++k) {
      EXPECT_LT((segment.curve.evaluate(k / 10.0) - closed.evaluate(segment.interval.at(k / 10.0)))
                    .norm(),
                1e-12);
    }
  }
}

TEST(BSplineCurve, SamplingIsUniformInParameterAndClampedCurvesInterpolateEnds) {
  std::mt19937 rng(39);
  const std::vector<Vector3d> points = d2vdb::test::randomPoints(rng, 6, true);
  const BSplineCurve curve = BSplineCurve::clamped(3, points, 2, {1.0, 3.0});
  const std::vector<Vector3d> samples = curve.sample(5);
  ASSERT_EQ(samples.size(), 5u);
  EXPECT_EQ(samples.front(), points.front());
  EXPECT_LT((samples.back() - points.back()).norm(), 1e-15);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(samples[static_cast<std::size_t>(i)], curve.evaluate(1.0 + 0.5 * i));
    EXPECT_EQ(samples[static_cast<std::size_t>(i)].z(), 0.0);
  }
  EXPECT_THROW(curve.sample(1), InputError);
}

TEST(BSplineCurve, ParametersOutsideTheDomainOfAnOpenCurveAreRejected) {
  const BSplineCurve curve = BSplineCurve::clamped(2, {{0, 0, 0}, {1, 1, 0}, {2, 0, 0}});
  expectInputError([&] { curve.evaluate(1.5); }, "outside the domain [0, 1]");
  EXPECT_THROW(curve.derivatives(-0.1), InputError);
  EXPECT_THROW(curve.evaluate(std::nan("")), InputError);
  EXPECT_THROW(curve.derivative(0.5, -1), InputError);
  const BSplineCurve closed = BSplineCurve::closed(2, {{0, 0, 0}, {1, 1, 0}, {2, 0, 0}});
  EXPECT_THROW(closed.evaluate(std::numeric_limits<double>::infinity()), InputError);
}

TEST(BSplineCurve, ValidationRejectsBadCurvesWithClearMessages) {
  const std::vector<Vector3d> points{{0, 0, 0}, {1, 1, 0}, {2, 0, 0}, {3, 1, 0}};
  expectInputError([&] { BSplineCurve(KnotVector::clamped(2, 5), points); },
                   "4 control points but the 8 knots of degree 2 need 5");
  expectInputError([&] { BSplineCurve(KnotVector::clamped(2, 4), points, 4); },
                   "dimension 4 is not supported");
  std::vector<Vector3d> lifted = points;
  lifted[2].z() = 0.25;
  expectInputError([&] { BSplineCurve::clamped(2, lifted, 2); },
                   "control point 2 (2, 0, 0.25) has z != 0");
  std::vector<Vector3d> broken = points;
  broken[1].x() = std::numeric_limits<double>::infinity();
  expectInputError([&] { BSplineCurve::clamped(2, broken); }, "control point 1 (inf, 1, 0)");
  expectInputError(
      [&] {
        BSplineCurve::closed(3, {points[0], points[1], points[2]});
      },
      "too few for degree 3");
  std::vector<double> uneven = KnotVector::periodic(2, 4).values();
  uneven[4] += 0.1;
  expectInputError([&] { BSplineCurve(KnotVector(2, uneven), points, 3, true); },
                   "uniform periodic");
  // An equally spaced unclamped vector is the periodic one: accepted.
  EXPECT_NO_THROW(BSplineCurve(KnotVector::uniform(2, 6), points, 3, true));
  expectInputError([&] { BSplineCurve(KnotVector::clamped(2, 6), points, 3, true); },
                   "uniform periodic");
  expectInputError([&] { BSplineCurve(KnotVector::periodic(2, 5), points, 3, true); },
                   "needs 9 knots");

  BSplineCurve curve = BSplineCurve::clamped(2, points, 2);
  EXPECT_THROW(curve.setControlPoints(lifted), InputError);
  EXPECT_THROW(curve.setControlPoints({points[0]}), InputError);
  EXPECT_EQ(curve.controlPoints(), points);  // unchanged after the failures
  std::vector<Vector3d> moved = points;
  moved[0].y() = 5.0;
  curve.setControlPoints(moved);
  EXPECT_EQ(curve.evaluate(0.0), moved[0]);
}

TEST(BSplineCurve, AcceptsAClosedKnotVectorWithinRoundingAndStoresTheExactOne) {
  std::vector<double> knots = KnotVector::periodic(2, 4, {0.0, 1.0}).values();
  knots[3] += 1e-13;
  const std::vector<Vector3d> points{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const BSplineCurve curve(KnotVector(2, knots), points, 2, true);
  EXPECT_EQ(curve.knots(), KnotVector::periodic(2, 4, {0.0, 1.0}));
}

TEST(BSplineCurve, HighDegreeCurvesEvaluateConsistently) {
  std::mt19937 rng(40);
  const int degree = d2vdb::kMaxSplineDegree;
  const BSplineCurve curve = BSplineCurve::clamped(degree, d2vdb::test::randomPoints(rng, 20));
  const std::vector<d2vdb::BezierSegment> segments = curve.toBezierSegments();
  for (const d2vdb::BezierSegment& segment : segments) {
    for (int k = 0; k <= 5; ++k) {
      EXPECT_LT(
          (segment.curve.evaluate(k / 5.0) - curve.evaluate(segment.interval.at(k / 5.0))).norm(),
          1e-10);
    }
  }
}

}  // namespace
