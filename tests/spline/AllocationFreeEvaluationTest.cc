// Checks the documented guarantee that evaluation does not allocate heap memory, by counting
// calls to the global allocation functions (replaced for this test executable).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include "d2vdb/spline/BSplineCurve.h"
#include "d2vdb/spline/BSplineSurface.h"
#include "d2vdb/spline/BasisFunctions.h"
#include "d2vdb/spline/Bernstein.h"
#include "spline/SplineTestSupport.h"

namespace {
std::atomic<long> allocationCount{0};

void* countedAllocation(std::size_t size) {
  ++allocationCount;
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}

void* countedAlignedAllocation(std::size_t size, std::align_val_t alignment) {
  ++allocationCount;
  const std::size_t align = static_cast<std::size_t>(alignment);
  const std::size_t rounded = (size + align - 1) / align * align;
  if (void* memory = std::aligned_alloc(align, rounded == 0 ? align : rounded)) return memory;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) {
  return countedAllocation(size);
}
void* operator new[](std::size_t size) {
  return countedAllocation(size);
}
void* operator new(std::size_t size, std::align_val_t alignment) {
  return countedAlignedAllocation(size, alignment);
}
void* operator new[](std::size_t size, std::align_val_t alignment) {
  return countedAlignedAllocation(size, alignment);
}
void operator delete(void* memory) noexcept {
  std::free(memory);
}
void operator delete[](void* memory) noexcept {
  std::free(memory);
}
void operator delete(void* memory, std::size_t) noexcept {
  std::free(memory);
}
void operator delete[](void* memory, std::size_t) noexcept {
  std::free(memory);
}
void operator delete(void* memory, std::align_val_t) noexcept {
  std::free(memory);
}
void operator delete[](void* memory, std::align_val_t) noexcept {
  std::free(memory);
}
void operator delete(void* memory, std::size_t, std::align_val_t) noexcept {
  std::free(memory);
}
void operator delete[](void* memory, std::size_t, std::align_val_t) noexcept {
  std::free(memory);
}

namespace {

using Eigen::Vector3d;

TEST(AllocationFreeEvaluation, CountingWorks) {
  const long before = allocationCount.load();
  auto* probe = new std::vector<int>(100);
  delete probe;
  EXPECT_GE(allocationCount.load() - before, 2);
}

TEST(AllocationFreeEvaluation, CurveSurfaceBasisAndBernsteinHotPathsDoNotAllocate) {
  std::mt19937 rng(91);
  const d2vdb::BSplineCurve open =
      d2vdb::BSplineCurve::clamped(d2vdb::kMaxSplineDegree, d2vdb::test::randomPoints(rng, 30));
  const d2vdb::BSplineCurve closed =
      d2vdb::BSplineCurve::closed(3, d2vdb::test::randomPoints(rng, 9));
  const d2vdb::BSplineSurface surface(d2vdb::KnotVector::clamped(5, 8),
                                      d2vdb::KnotVector::periodic(3, 7),
                                      d2vdb::test::randomPoints(rng, 8 * 7), false, true);
  const d2vdb::BernsteinPolynomial polynomial(std::vector<double>(12, 0.5));
  const d2vdb::BezierCurve bezier(d2vdb::test::randomPoints(rng, 12));
  Vector3d sink = Vector3d::Zero();
  double scalarSink = 0.0;

  const long before = allocationCount.load();
  for (int k = 0; k <= 100; ++k) {
    const double t = k / 100.0;
    sink += open.evaluate(t) + open.derivatives(t).second + open.derivative(t, 3);
    sink += closed.evaluate(t + 0.5) + closed.derivatives(t - 2.0).first;
    sink += surface.evaluate(t, 1.0 - t) + surface.derivatives(t, t).duv;
    const int span = open.knots().findSpan(t);
    scalarSink += d2vdb::basisValues(open.knots(), span, t).sum();
    scalarSink += d2vdb::basisDerivatives(open.knots(), span, t, 4).sum();
    scalarSink += polynomial.evaluate(t) + polynomial.subdivide(t).first.evaluate(0.5);
    scalarSink += (polynomial * polynomial.derivative()).maxCoefficient();
    sink += bezier.evaluate(t) + bezier.subdivide(t).second.derivative().evaluate(0.5);
    scalarSink += dot(bezier, bezier.derivative()).evaluate(t);
  }
  EXPECT_EQ(allocationCount.load() - before, 0);
  EXPECT_TRUE(sink.allFinite());
  EXPECT_TRUE(std::isfinite(scalarSink));
}

}  // namespace
