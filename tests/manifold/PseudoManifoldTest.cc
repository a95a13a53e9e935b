// The parametric pseudo-manifold: C-infinity continuity shown to round-off across edges and at
// vertices, steps between neighbouring samples shrinking with the sampling step, exact
// reproduction of polynomials by the chart fit, affine invariance of the Loop-based surface,
// fidelity to the Loop source, derivatives against finite differences, determinism.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <random>
#include <vector>

#include "ManifoldTestSupport.h"
#include "d2vdb/core/Error.h"
#include "d2vdb/manifold/BumpFunction.h"
#include "d2vdb/manifold/LoopLimitSurface.h"
#include "d2vdb/manifold/PnTriangles.h"
#include "d2vdb/manifold/PseudoManifold.h"
#include "d2vdb/manifold/SourceDistance.h"
#include "d2vdb/mesh/MeshIO.h"

namespace d2vdb {
namespace {

using test::DoubleMesh;
using Index = HalfEdgeMesh::Index;

struct Built {
  std::shared_ptr<const HalfEdgeMesh> mesh;
  std::unique_ptr<LoopLimitSurface> loop;
  std::unique_ptr<PseudoManifold> pps;
};

Built buildLoop(const DoubleMesh& m, const PseudoManifoldOptions& options = {}) {
  Built b;
  b.mesh = m.build();
  b.loop = std::make_unique<LoopLimitSurface>(b.mesh);
  b.pps = std::make_unique<PseudoManifold>(*b.loop, options);
  return b;
}

std::vector<std::pair<const char*, DoubleMesh>> continuityMeshes() {
  return {{"tetrahedron", test::tetrahedron()},
          {"octahedron", test::octahedron()},
          {"icosahedron", test::icosphere(0)},
          {"degrees 3-9", test::mixedDegreeMesh()}};
}

/// Face point of half-edge h's face at fraction t from from(h) to to(h) (on the edge).
FacePoint onEdge(Index h, double t) {
  FacePoint p{HalfEdgeMesh::face(h), Eigen::Vector3d::Zero()};
  p.bary[h % 3] = 1.0 - t;
  p.bary[(h + 1) % 3] = t;
  return p;
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

TEST(PseudoManifold, EdgesAndVerticesAgreeToRoundOff) {
  auto meshes = continuityMeshes();
  meshes.emplace_back("bipyramid (degree 16)", test::bipyramid(16));
  for (const auto& [name, m] : meshes) {
    const Built b = buildLoop(m);
    const HalfEdgeMesh& mesh = *b.mesh;
    const double diagonal = mesh.boundingBoxDiagonal();
    double worstPosition = 0.0, worstNormal = 0.0, worstCurvature = 0.0, worstDirection = 0.0;
    for (Index h = 0; h < mesh.halfEdgeCount(); ++h) {
      const Index t = mesh.twin(h);
      for (const double s : {0.0, 0.03, 0.1, 0.25, 0.5, 0.61, 0.77, 0.93, 1.0}) {
        const SmoothPoint a = b.pps->evaluate(onEdge(h, s), Derivatives::Second);
        const SmoothPoint c = b.pps->evaluate(onEdge(t, 1.0 - s), Derivatives::Second);
        worstPosition = std::max(worstPosition, (a.position - c.position).norm() / diagonal);
        worstNormal = std::max(worstNormal, angleBetween(a.normal, c.normal));
        const double scale = std::max({std::abs(a.k1), std::abs(a.k2), 1.0 / diagonal});
        worstCurvature = std::max(
            {worstCurvature, std::abs(a.k1 - c.k1) / scale, std::abs(a.k2 - c.k2) / scale});
        if (a.k1 - a.k2 > 1e-3 * scale) {
          worstDirection = std::max(worstDirection, 1.0 - std::abs(a.e1.dot(c.e1)));
        }
      }
    }
    // Every face around every vertex gives the vertex's own shape function value psi_v(0).
    for (Index v = 0; v < mesh.vertexCount(); ++v) {
      const Eigen::Vector3d center = b.pps->shapeFunction({v, Eigen::Vector2d::Zero()});
      for (int k = 0; k < mesh.degree(v); ++k) {
        const SmoothPoint p = b.pps->evaluate(onEdge(mesh.ring(v, k), 0.0), Derivatives::First);
        worstPosition = std::max(worstPosition, (p.position - center).norm() / diagonal);
        const SmoothPoint q = b.pps->evaluate(onEdge(mesh.ring(v, 0), 0.0), Derivatives::First);
        worstNormal = std::max(worstNormal, angleBetween(p.normal, q.normal));
      }
    }
    std::printf("%s: position %.3g of the diagonal, normal %.3g rad, curvature %.3g, e1 %.3g\n",
                name, worstPosition, worstNormal, worstCurvature, worstDirection);
    EXPECT_LE(worstPosition, 1e-12) << name;
    EXPECT_LE(worstNormal, 1e-10) << name;
    EXPECT_LE(worstCurvature, 1e-8) << name;
    EXPECT_LE(worstDirection, 1e-8) << name;
  }
}

/// Largest distance between neighbouring points of the lattice with G intervals per edge, over
/// 20 stations along every edge (and their lattice neighbours in both faces) and the lattice
/// neighbours of every vertex in each of its faces: where a discontinuity would show.
double largestStep(const PseudoManifold& pps, long g) {
  const HalfEdgeMesh& mesh = pps.mesh();
  double worst = 0.0;
  const auto point = [&](Index face, long i, long j) {
    const double s = static_cast<double>(g);
    return pps.position({face, Eigen::Vector3d((g - i - j) / s, i / s, j / s)});
  };
  const long neighbors[6][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, -1}, {-1, 1}};
  const auto stepsAround = [&](Index face, long i, long j) {
    const Eigen::Vector3d center = point(face, i, j);
    for (const auto& n : neighbors) {
      const long a = i + n[0];
      const long b = j + n[1];
      if (a < 0 || b < 0 || a + b > g) continue;
      worst = std::max(worst, (point(face, a, b) - center).norm());
    }
  };
  for (Index f = 0; f < mesh.faceCount(); ++f) {
    // Stations on the edge b2 = 0 (corner 0 to 1) of every face: each edge is seen from both
    // of its faces; then the three corners.
    for (long station = 0; station <= 20; ++station) {
      const long i = station * g / 20;
      for (int rotation = 0; rotation < 3; ++rotation) {
        // Edge from corner `rotation` to the next: lattice (i, j) in that corner's terms.
        const long b0 = g - i;
        const long b1 = i;
        long coords[3] = {0, 0, 0};
        coords[rotation] = b0;
        coords[(rotation + 1) % 3] = b1;
        stepsAround(f, coords[1], coords[2]);
      }
    }
  }
  return worst;
}

TEST(PseudoManifold, StepsShrinkWithTheSamplingStep) {
  for (const auto& [name, m] : continuityMeshes()) {
    const Built b = buildLoop(m);
    std::vector<double> scaled;
    for (const long g : {60L, 240L, 960L, 3840L}) {
      const double step = largestStep(*b.pps, g);
      scaled.push_back(step * g / b.mesh->boundingBoxDiagonal());
    }
    std::printf("%s: largest step x G / diagonal at G = 60, 240, 960, 3840: %.4g %.4g %.4g %.4g\n",
                name, scaled[0], scaled[1], scaled[2], scaled[3]);
    // Proportional to 1/G: the scaled step settles to the largest derivative (within 2 %
    // from G = 240 on), never grows.
    for (std::size_t i = 1; i < scaled.size(); ++i) {
      EXPECT_LT(scaled[i], 1.02 * scaled[i - 1]) << name;
      EXPECT_GT(scaled[i], 0.5 * scaled[0]) << name;
    }
    EXPECT_NEAR(scaled[3], scaled[2], 0.02 * scaled[2]) << name;
  }
}

TEST(PseudoManifold, NormalsAndCurvaturesVaryContinuouslyAcrossEdges) {
  // C2 across edges: geometry at distance +-eps on both sides of an edge differs by O(eps).
  const Built b = buildLoop(test::mixedDegreeMesh());
  const HalfEdgeMesh& mesh = *b.mesh;
  std::vector<double> worst;
  for (const double eps : {1e-4, 1e-5, 1e-6}) {
    double w = 0.0;
    for (Index h = 0; h < mesh.halfEdgeCount(); h += 3) {
      const Index t = mesh.twin(h);
      for (const double s : {0.2, 0.5, 0.8}) {
        FacePoint a = onEdge(h, s);
        FacePoint c = onEdge(t, 1.0 - s);
        a.bary *= 1.0 - eps;
        a.bary[(h + 2) % 3] = eps;
        c.bary *= 1.0 - eps;
        c.bary[(t + 2) % 3] = eps;
        const SmoothPoint pa = b.pps->evaluate(a, Derivatives::Second);
        const SmoothPoint pc = b.pps->evaluate(c, Derivatives::Second);
        w = std::max({w, angleBetween(pa.normal, pc.normal), std::abs(pa.k1 - pc.k1),
                      std::abs(pa.k2 - pc.k2)});
      }
    }
    worst.push_back(w);
  }
  std::printf(
      "largest normal/curvature jump across edges at eps 1e-4, 1e-5, 1e-6: %.3g %.3g %.3g\n",
      worst[0], worst[1], worst[2]);
  EXPECT_NEAR(worst[1] / worst[0], 0.1, 0.02);
  EXPECT_NEAR(worst[2] / worst[1], 0.1, 0.02);
}

/// A source whose points, on the faces around vertex `center`, are a given polynomial of the
/// chart coordinates of `center`: psi_centre must reproduce it.
class PolynomialSource final : public SourceSurface {
 public:
  PolynomialSource(std::shared_ptr<const HalfEdgeMesh> mesh, Index center, int bidegree)
      : mesh_(std::move(mesh)), atlas_(*mesh_), center_(center), bidegree_(bidegree) {}
  const HalfEdgeMesh& mesh() const override { return *mesh_; }
  std::shared_ptr<const HalfEdgeMesh> sharedMesh() const override { return mesh_; }
  void positions(Index face, const Eigen::Vector3d* bary, std::size_t count,
                 Eigen::Vector3d* out) const override {
    for (std::size_t i = 0; i < count; ++i) out[i] = evaluate({face, bary[i]}).position;
  }
  SourceJet evaluate(const FacePoint& point) const override {
    for (int corner = 0; corner < 3; ++corner) {
      if (mesh_->corner(point.face, corner) == center_) {
        return {polynomial(atlas_.toChart(point, corner).p), {}, {}, true};
      }
    }
    return {Eigen::Vector3d::Zero(), {}, {}, true};
  }
  std::string name() const override { return "polynomial"; }
  /// A polynomial with every monomial x^a y^b, a, b <= bidegree.
  Eigen::Vector3d polynomial(const Eigen::Vector2d& p) const {
    Eigen::Vector3d value = Eigen::Vector3d::Zero();
    for (int a = 0; a <= bidegree_; ++a) {
      for (int c = 0; c <= bidegree_; ++c) {
        const double m = std::pow(p.x(), a) * std::pow(p.y(), c);
        value += m * Eigen::Vector3d(1.0 + 0.3 * a - 0.2 * c, 0.5 * a * c - 1.0, 0.1 * (a + c));
      }
    }
    return value;
  }

 private:
  std::shared_ptr<const HalfEdgeMesh> mesh_;
  ChartAtlas atlas_;
  Index center_;
  int bidegree_;
};

/// Calls check(mesh, v, n, d, source, pps) for one vertex v of each degree n = 3..9 of the
/// mixed-degree mesh (bidegree d = 4..7), source a polynomial of bidegree d in v's chart and pps
/// the pseudo-manifold built from it; returns the number of degrees visited.
template <typename Check>
int forOneVertexOfEachDegree(Check check) {
  const DoubleMesh mixed = test::mixedDegreeMesh();
  const auto mesh = mixed.build();
  std::vector<bool> seen(16, false);
  int visited = 0;
  for (Index v = 0; v < mesh->vertexCount(); ++v) {
    const int n = mesh->degree(v);
    if (seen[n]) continue;
    seen[n] = true;
    const int d = std::min(n + 1, 7);
    const PolynomialSource source(mesh, v, d);
    const PseudoManifold pps(source);
    check(mesh, v, n, d, source, pps);
    ++visited;
  }
  return visited;
}

TEST(PseudoManifold, ChartFitReproducesPolynomialsOfItsBidegree) {
  const int tested =
      forOneVertexOfEachDegree([](const auto&, Index v, int n, int d,
                                  const PolynomialSource& source, const PseudoManifold& pps) {
        ASSERT_EQ(pps.bidegree(v), d);
        double worst = 0.0;
        double size = 0.0;
        const double radius = ChartAtlas::radius(n);
        for (int i = 0; i <= 20; ++i) {
          for (int j = 0; j <= 20; ++j) {
            const Eigen::Vector2d p(radius * (i / 10.0 - 1.0), radius * (j / 10.0 - 1.0));
            if (p.norm() >= radius) continue;
            const Eigen::Vector3d expected = source.polynomial(p);
            worst = std::max(worst, (pps.shapeFunction({v, p}) - expected).norm());
            size = std::max(size, expected.norm());
          }
        }
        std::printf(
            "degree %d, bidegree %d: largest error %.3g of the largest value (condition %.3g)\n", n,
            d, worst / size, pps.fitConditionNumber(n));
        EXPECT_LT(worst / size, 1e-11) << "degree " << n;
      });
  EXPECT_EQ(tested, 7);
}

/// d^i/dx^i d^j/dy^j of x^a y^c at p (exact).
double monomialDerivative(const Eigen::Vector2d& p, int a, int c, int i, int j) {
  if (i > a || j > c) return 0.0;
  double factor = 1.0;
  for (int k = 0; k < i; ++k) factor *= a - k;
  for (int k = 0; k < j; ++k) factor *= c - k;
  return factor * std::pow(p.x(), a - i) * std::pow(p.y(), c - j);
}

TEST(PseudoManifold, ThirdDerivativesReproducePolynomialsOfTheBidegree) {
  // Where only the chart of v covers the surface, the surface is psi_v, which reproduces the
  // source polynomial: its third derivatives in v's chart are the polynomial's, exactly.
  const int tested =
      forOneVertexOfEachDegree([](const auto& mesh, Index v, int n, int d, const PolynomialSource&,
                                  const PseudoManifold& pps) {
        const double radius = ChartAtlas::radius(n);
        double worst = 0.0;
        double size = 0.0;
        int points = 0;
        for (int i = 0; i <= 20; ++i) {
          for (int j = 0; j <= 20; ++j) {
            const Eigen::Vector2d p(radius * (i / 40.0 - 0.25), radius * (j / 40.0 - 0.25));
            const FacePoint q = pps.atlas().fromChart({v, p});
            int corner = -1;
            bool alone = true;
            for (int k = 0; k < 3; ++k) {
              if (mesh->corner(q.face, k) == v) {
                corner = k;
              } else if (ChartAtlas::inChart(q.bary, k)) {
                alone = false;
              }
            }
            ASSERT_GE(corner, 0);
            if (!alone) continue;
            const SmoothThirdDerivatives x = pps.chartThirdDerivatives(q, corner);
            for (int m = 0; m < 4; ++m) {
              Eigen::Vector3d expected = Eigen::Vector3d::Zero();
              for (int a = 0; a <= d; ++a) {
                for (int c = 0; c <= d; ++c) {
                  expected +=
                      monomialDerivative(p, a, c, 3 - m, m) *
                      Eigen::Vector3d(1.0 + 0.3 * a - 0.2 * c, 0.5 * a * c - 1.0, 0.1 * (a + c));
                }
              }
              worst = std::max(worst, (x.ddd[m] - expected).norm());
              size = std::max(size, expected.norm());
            }
            ++points;
          }
        }
        std::printf(
            "degree %d, bidegree %d: third derivatives at %d points, largest error %.3g of "
            "the largest\n",
            n, d, points, worst / size);
        EXPECT_GT(points, 100) << "degree " << n;
        EXPECT_LT(worst / size, 1e-10) << "degree " << n;
      });
  EXPECT_EQ(tested, 7);
}

TEST(PseudoManifold, LoopBasedSurfaceIsAffineInvariant) {
  const DoubleMesh m = test::mixedDegreeMesh();
  Eigen::Matrix3d a;
  a << 1.3, 0.4, -0.2, -0.3, 0.9, 0.5, 0.2, -0.6, 1.7;
  const Eigen::Vector3d shift(10.0, -4.0, 2.5);
  DoubleMesh moved = m;
  for (Eigen::Vector3d& p : moved.positions) p = a * p + shift;
  const Built original = buildLoop(m);
  const Built image = buildLoop(moved);
  double worst = 0.0;
  double size = 0.0;
  for (Index f = 0; f < original.mesh->faceCount(); ++f) {
    for (const Eigen::Vector3d& bary : faceLattice(4)) {
      const Eigen::Vector3d expected = a * original.pps->position({f, bary}) + shift;
      worst = std::max(worst, (image.pps->position({f, bary}) - expected).norm());
      size = std::max(size, expected.norm());
    }
  }
  std::printf("affine image: largest difference %.3g of the largest coordinate\n", worst / size);
  EXPECT_LT(worst / size, 1e-10);
}

TEST(PseudoManifold, WeightsHaveTheirExactValues) {
  const Built b = buildLoop(test::mixedDegreeMesh());
  for (Index v = 0; v < b.mesh->vertexCount(); v += 13) {
    const double r = ChartAtlas::radius(b.mesh->degree(v));
    const Eigen::Vector2d direction = Eigen::Vector2d(0.6, -0.8);
    EXPECT_EQ(b.pps->weight({v, Eigen::Vector2d::Zero()}), 1.0);
    EXPECT_EQ(b.pps->weight({v, 0.25 * r * direction}), 1.0);
    EXPECT_NEAR(b.pps->weight({v, 0.625 * r * direction}), 0.5, 1e-15);
    EXPECT_EQ(b.pps->weight({v, r * direction}), 0.0);
    EXPECT_EQ(b.pps->weight({v, 1.5 * r * direction}), 0.0);
  }
}

/// Calls visit(point, corner) for every `faceStep`-th face of `mesh`, each of the barycentric
/// points `barys` on it and each corner whose chart contains the point.
template <typename Visit>
void forEachChartPoint(const HalfEdgeMesh& mesh, Index faceStep,
                       std::initializer_list<Eigen::Vector3d> barys, Visit visit) {
  for (Index f = 0; f < mesh.faceCount(); f += faceStep) {
    for (const Eigen::Vector3d& bary : barys) {
      for (int corner = 0; corner < 3; ++corner) {
        if (ChartAtlas::inChart(bary, corner)) visit(FacePoint{f, bary}, corner);
      }
    }
  }
}

TEST(PseudoManifold, DerivativesMatchFiniteDifferences) {
  const Built b = buildLoop(test::mixedDegreeMesh());
  const HalfEdgeMesh& mesh = *b.mesh;
  double worstFirst = 0.0;
  double worstSecond = 0.0;
  const double h = 1e-4;
  forEachChartPoint(
      mesh, 11,
      {Eigen::Vector3d(0.2, 0.3, 0.5), Eigen::Vector3d(0.7, 0.2, 0.1),
       Eigen::Vector3d(0.05, 0.9, 0.05), Eigen::Vector3d(1.0, 0.0, 0.0)},
      [&](const FacePoint& point, int corner) {
        const SmoothDerivatives d = b.pps->chartDerivatives(point, corner);
        const ChartPoint c = b.pps->atlas().toChart(point, corner);
        const auto at = [&](double dx, double dy) {
          return b.pps->position(
              b.pps->atlas().fromChart({c.vertex, c.p + Eigen::Vector2d(dx, dy)}));
        };
        const Eigen::Vector3d fx = (at(h, 0) - at(-h, 0)) / (2 * h);
        const Eigen::Vector3d fy = (at(0, h) - at(0, -h)) / (2 * h);
        const Eigen::Vector3d fxx = (at(h, 0) - 2.0 * d.position + at(-h, 0)) / (h * h);
        const Eigen::Vector3d fyy = (at(0, h) - 2.0 * d.position + at(0, -h)) / (h * h);
        const Eigen::Vector3d fxy = (at(h, h) - at(h, -h) - at(-h, h) + at(-h, -h)) / (4 * h * h);
        const double scale1 = std::max(d.d[0].norm(), d.d[1].norm());
        worstFirst =
            std::max({worstFirst, (fx - d.d[0]).norm() / scale1, (fy - d.d[1]).norm() / scale1});
        const double scale2 = std::max({d.dd[0].norm(), d.dd[1].norm(), d.dd[2].norm(), scale1});
        worstSecond = std::max({worstSecond, (fxx - d.dd[0]).norm() / scale2,
                                (fxy - d.dd[1]).norm() / scale2, (fyy - d.dd[2]).norm() / scale2});
      });
  std::printf("chart derivatives against central differences: first %.3g, second %.3g\n",
              worstFirst, worstSecond);
  EXPECT_LT(worstFirst, 1e-6);
  EXPECT_LT(worstSecond, 1e-4);
}

TEST(PseudoManifold, ThirdDerivativesMatchFiniteDifferencesOfTheSecond) {
  // Points where two or three charts blend (every chain rule: polar maps of degrees 3 to 9 and
  // 6, weights, patches, quotient), third derivatives against central differences of the
  // (exact) second derivatives in the same chart; each third derivative is checked twice where
  // it is a derivative of two different second derivatives.
  const Built b = buildLoop(test::mixedDegreeMesh());
  const HalfEdgeMesh& mesh = *b.mesh;
  double worst = 0.0;
  double worstLower = 0.0;
  const double h = 2e-5;
  int points = 0;
  forEachChartPoint(
      mesh, 7,
      {Eigen::Vector3d(0.2, 0.3, 0.5), Eigen::Vector3d(0.7, 0.2, 0.1),
       Eigen::Vector3d(0.05, 0.9, 0.05), Eigen::Vector3d(0.45, 0.45, 0.1),
       Eigen::Vector3d(1.0, 0.0, 0.0)},
      [&](const FacePoint& point, int corner) {
        const SmoothThirdDerivatives x = b.pps->chartThirdDerivatives(point, corner);
        const SmoothDerivatives lower = b.pps->chartDerivatives(point, corner);
        const ChartPoint c = b.pps->atlas().toChart(point, corner);
        const auto secondAt = [&](double dx, double dy) {
          const FacePoint q = b.pps->atlas().fromChart({c.vertex, c.p + Eigen::Vector2d(dx, dy)});
          for (int k = 0; k < 3; ++k) {
            if (mesh.corner(q.face, k) == c.vertex) return b.pps->chartDerivatives(q, k);
          }
          ADD_FAILURE() << "no corner of vertex " << c.vertex;
          return SmoothDerivatives{};
        };
        const SmoothDerivatives px = secondAt(h, 0), mx = secondAt(-h, 0);
        const SmoothDerivatives py = secondAt(0, h), my = secondAt(0, -h);
        const Eigen::Vector3d dx[3] = {(px.dd[0] - mx.dd[0]) / (2 * h),
                                       (px.dd[1] - mx.dd[1]) / (2 * h),
                                       (px.dd[2] - mx.dd[2]) / (2 * h)};
        const Eigen::Vector3d dy[3] = {(py.dd[0] - my.dd[0]) / (2 * h),
                                       (py.dd[1] - my.dd[1]) / (2 * h),
                                       (py.dd[2] - my.dd[2]) / (2 * h)};
        double scale = 0.0;
        for (const Eigen::Vector3d& t : x.ddd) scale = std::max(scale, t.norm());
        for (const Eigen::Vector3d& t : x.dd) scale = std::max(scale, t.norm());
        const Eigen::Vector3d differences[6] = {dx[0] - x.ddd[0], dy[0] - x.ddd[1],
                                                dx[1] - x.ddd[1], dy[1] - x.ddd[2],
                                                dx[2] - x.ddd[2], dy[2] - x.ddd[3]};
        for (const Eigen::Vector3d& e : differences) worst = std::max(worst, e.norm() / scale);
        // The lower derivatives are those of the order-2 evaluation to round-off (the order-3
        // evaluation blends with normalised weights).
        worstLower = std::max({worstLower, (x.position - lower.position).norm(),
                               (x.d[0] - lower.d[0]).norm(), (x.d[1] - lower.d[1]).norm(),
                               (x.dd[0] - lower.dd[0]).norm(), (x.dd[1] - lower.dd[1]).norm(),
                               (x.dd[2] - lower.dd[2]).norm()});
        ++points;
      });
  std::printf(
      "third chart derivatives at %d points against central differences of the second: "
      "largest error %.3g of the largest derivative; lower orders differ by %.3g\n",
      points, worst, worstLower);
  EXPECT_GT(points, 100);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worstLower, 1e-12);
}

TEST(PseudoManifold, FaceAndChartDerivativesGiveTheSameGeometry) {
  const Built b = buildLoop(test::mixedDegreeMesh());
  double worst = 0.0;
  for (Index f = 0; f < b.mesh->faceCount(); f += 5) {
    const FacePoint point{f, Eigen::Vector3d(0.3, 0.45, 0.25)};
    const std::optional<SmoothDerivatives> face = b.pps->faceDerivatives(point);
    ASSERT_TRUE(face.has_value());
    const SmoothPoint g1 = surfaceGeometry(*face);
    for (int corner = 0; corner < 3; ++corner) {
      const SmoothPoint g2 = surfaceGeometry(b.pps->chartDerivatives(point, corner));
      worst = std::max({worst, (g1.position - g2.position).norm(), (g1.normal - g2.normal).norm(),
                        std::abs(g1.k1 - g2.k1), std::abs(g1.k2 - g2.k2)});
    }
  }
  EXPECT_LT(worst, 1e-11);
  // At a corner of degree != 6 the face parametrisation has no derivative.
  const DoubleMesh tetra = test::tetrahedron();
  const Built t = buildLoop(tetra);
  EXPECT_FALSE(t.pps->faceDerivatives({0, Eigen::Vector3d(1.0, 0.0, 0.0)}).has_value());
  EXPECT_TRUE(t.pps->faceDerivatives({0, Eigen::Vector3d(0.9, 0.1, 0.0)}).has_value());
}

TEST(PseudoManifold, SurfaceGeometryOfAnEllipsoid) {
  // X(s, t) = (a cos s cos t, b sin s cos t, c sin t) at s = 0.3, t = 0.2 against the closed-form
  // Gaussian and mean curvature of the ellipsoid (outward normal, k > 0).
  const double a = 3.0, b = 2.0, c = 1.0, s = 0.3, t = 0.2;
  SmoothDerivatives d;
  d.position = {a * std::cos(s) * std::cos(t), b * std::sin(s) * std::cos(t), c * std::sin(t)};
  d.d[0] = {-a * std::sin(s) * std::cos(t), b * std::cos(s) * std::cos(t), 0.0};
  d.d[1] = {-a * std::cos(s) * std::sin(t), -b * std::sin(s) * std::sin(t), c * std::cos(t)};
  d.dd[0] = {-a * std::cos(s) * std::cos(t), -b * std::sin(s) * std::cos(t), 0.0};
  d.dd[1] = {a * std::sin(s) * std::sin(t), -b * std::cos(s) * std::sin(t), 0.0};
  d.dd[2] = {-a * std::cos(s) * std::cos(t), -b * std::sin(s) * std::cos(t), -c * std::sin(t)};
  const SmoothPoint g = surfaceGeometry(d);
  const Eigen::Vector3d x = d.position;
  const double q = x.x() * x.x() / std::pow(a, 4) + x.y() * x.y() / std::pow(b, 4) +
                   x.z() * x.z() / std::pow(c, 4);
  const double gauss = 1.0 / (a * a * b * b * c * c * q * q);
  const double mean =
      (x.squaredNorm() - a * a - b * b - c * c) / (2.0 * a * a * b * b * c * c * std::pow(q, 1.5));
  EXPECT_NEAR(g.k1 * g.k2, gauss, 1e-12);
  EXPECT_NEAR(0.5 * (g.k1 + g.k2), -mean, 1e-12);
  EXPECT_GT(g.normal.dot(x), 0.0);
  EXPECT_GE(g.k1, g.k2);
  EXPECT_NEAR(g.e1.dot(g.normal), 0.0, 1e-14);
  EXPECT_NEAR(g.e2.dot(g.normal.cross(g.e1)), 1.0, 1e-14);
}

TEST(PseudoManifold, CloseToItsLoopSource) {
  // A torus with every vertex of degree 6, and meshes with degrees 3 to 9 (the bunny included):
  // distance from the PPS to the Loop limit surface at 4^3 samples per face (on every second
  // face of the torus and every eighth of the bunny here; all faces in BENCHMARKS.md).
  struct Case {
    const char* name;
    std::shared_ptr<const HalfEdgeMesh> mesh;
    double bound;
    int faceStep;  ///< every faceStep-th face, to keep the test fast
  };
  std::vector<Case> cases;
  cases.push_back({"torus 48 x 16", test::torus(3.0, 1.0, 48, 16).build(), 2e-5, 2});
  cases.push_back({"degrees 3-9", test::mixedDegreeMesh().build(), 1.5e-3, 1});
  cases.push_back(
      {"bunny",
       std::make_shared<const HalfEdgeMesh>(readMesh(D2VDB_SOURCE_DIR "/volumes/bunny.obj")),
       1.5e-3, 8});
  for (const Case& c : cases) {
    const LoopLimitSurface loop(c.mesh);
    const PseudoManifold pps(loop);
    const SourceDistanceStatistics s = distanceToSource(pps, loop, 8, c.faceStep);
    std::printf(
        "%s: distance to the Loop surface max %.3g, RMS %.3g of the diagonal "
        "(same parameters: max %.3g, RMS %.3g; %zu samples)\n",
        c.name, s.maxDistance / s.diagonal, s.rmsDistance / s.diagonal,
        s.maxParametric / s.diagonal, s.rmsParametric / s.diagonal, s.samples);
    EXPECT_LE(s.maxDistance / s.diagonal, c.bound) << c.name;
  }
}

TEST(PseudoManifold, SameResultForAnyThreadCount) {
  const DoubleMesh m = test::mixedDegreeMesh();
  const auto mesh = m.build();
  const LoopLimitSurface loop(mesh);
  std::vector<FacePoint> points;
  for (Index f = 0; f < mesh->faceCount(); ++f) {
    for (const Eigen::Vector3d& bary : faceLattice(3)) points.push_back({f, bary});
  }
  const auto run = [&] {
    const PseudoManifold pps(loop);
    std::vector<Eigen::Vector3d> controls;
    for (Index v = 0; v < mesh->vertexCount(); ++v) {
      for (const Eigen::Vector3d& c : pps.controlPoints(v)) controls.push_back(c);
    }
    return std::make_pair(controls, pps.evaluate(points, Derivatives::Second));
  };
  const auto one = test::withThreads(1, run);
  const auto two = test::withThreads(2, run);
  ASSERT_EQ(one.first.size(), two.first.size());
  for (std::size_t i = 0; i < one.first.size(); ++i) EXPECT_EQ(one.first[i], two.first[i]);
  ASSERT_EQ(one.second.size(), two.second.size());
  for (std::size_t i = 0; i < one.second.size(); ++i) {
    EXPECT_EQ(one.second[i].position, two.second[i].position);
    EXPECT_EQ(one.second[i].normal, two.second[i].normal);
    EXPECT_EQ(one.second[i].k1, two.second[i].k1);
    EXPECT_EQ(one.second[i].e1, two.second[i].e1);
  }
}

/// Dense samples of a pseudo-manifold (a lattice of 24 intervals per face), the brute-force
/// reference of the projection tests.
class DenseSurfaceSamples {
 public:
  explicit DenseSurfaceSamples(const Built& b) {
    for (Index f = 0; f < b.mesh->faceCount(); ++f) {
      for (const Eigen::Vector3d& bary : faceLattice(24)) {
        samples_.push_back({{f, bary}, b.pps->position({f, bary})});
      }
    }
  }

  /// The sample nearest to `x`: its (face, barycentric) point and its position.
  const std::pair<FacePoint, Eigen::Vector3d>& nearest(const Eigen::Vector3d& x) const {
    const auto* best = &samples_.front();
    for (const auto& s : samples_) {
      if ((s.second - x).norm() < (best->second - x).norm()) best = &s;
    }
    return *best;
  }

 private:
  std::vector<std::pair<FacePoint, Eigen::Vector3d>> samples_;
};

TEST(PseudoManifold, ProjectionFindsTheClosestPoint) {
  const Built b = buildLoop(test::icosphere(1));
  const DenseSurfaceSamples samples(b);
  for (const Eigen::Vector3d& x :
       {Eigen::Vector3d(1.3, 0.2, -0.1), Eigen::Vector3d(-0.2, 0.5, 0.6),
        Eigen::Vector3d(0.1, -1.1, 0.9), Eigen::Vector3d(0.0, 0.0, -2.0)}) {
    const auto& nearest = samples.nearest(x);
    const PseudoManifold::Projection p = b.pps->project(x, nearest.first);
    EXPECT_TRUE(p.converged);
    EXPECT_LE(p.distance, (nearest.second - x).norm() + 1e-15);
    // The residual is normal to the surface.
    const SmoothPoint g = b.pps->evaluate(p.point, Derivatives::First);
    EXPECT_LT((x - p.position).normalized().cross(g.normal).norm(), 1e-9);
  }
}

// Projections started from a nearby projection (its derivatives, no evaluation there), with the
// last step's geometry extrapolated, and stopped beyond a distance: the same footpoints as the
// projection from the nearest sample (the brute-force reference of the test above), geometry
// against an evaluation at the footpoint.
TEST(PseudoManifold, ProjectionFromANearbyProjection) {
  const Built b = buildLoop(test::icosphere(1));
  const DenseSurfaceSamples samples(b);
  const auto fromNearestSample = [&](const Eigen::Vector3d& x) {
    return b.pps->project(x, samples.nearest(x).first);
  };
  SmoothProjectionOptions extrapolate;
  extrapolate.extrapolateLastStep = true;
  // A line of equally spaced points outside and inside the surface, each projected from the one
  // before.
  for (const double offset : {0.15, -0.1}) {
    const Eigen::Vector3d direction = Eigen::Vector3d(0.3, 1.0, 0.2).normalized();
    const Eigen::Vector3d across = direction.cross(Eigen::Vector3d::UnitX()).normalized();
    PseudoManifold::Projection previous;
    bool havePrevious = false;
    int nearbyEvaluations = 0, sampleEvaluations = 0;
    for (int i = 0; i < 12; ++i) {
      const Eigen::Vector3d x = (1.0 + offset) * direction + 0.04 * i * across;
      const PseudoManifold::Projection reference = fromNearestSample(x);
      ASSERT_TRUE(reference.converged);
      if (havePrevious) {
        const PseudoManifold::Projection plain = b.pps->project(x, previous);
        EXPECT_TRUE(plain.converged);
        EXPECT_LT((plain.position - reference.position).norm(), 1e-11);
        EXPECT_NEAR(plain.distance, reference.distance, 1e-13);
        EXPECT_LT((plain.geometry.normal - reference.geometry.normal).norm(), 1e-10);
        EXPECT_NEAR(plain.geometry.k1, reference.geometry.k1, 1e-9);
        EXPECT_NEAR(plain.geometry.k2, reference.geometry.k2, 1e-9);
        nearbyEvaluations += plain.iterations;
        sampleEvaluations += reference.iterations;
        // Extrapolated: the same footpoint; position and normal to round-off, curvatures to
        // 1e-5 of their value (the sphere-like surface has k ~ 1).
        const PseudoManifold::Projection fast = b.pps->project(x, previous, extrapolate);
        EXPECT_TRUE(fast.converged);
        EXPECT_LE(fast.iterations, plain.iterations);
        EXPECT_LT((fast.position - reference.position).norm(), 1e-11);
        EXPECT_LT((fast.geometry.normal - reference.geometry.normal).norm(), 1e-10);
        EXPECT_NEAR(fast.geometry.k1, reference.geometry.k1,
                    1e-5 * std::abs(reference.geometry.k1));
        EXPECT_NEAR(fast.geometry.k2, reference.geometry.k2,
                    1e-5 * std::abs(reference.geometry.k2));
        const SmoothPoint exact = b.pps->evaluate(fast.point, Derivatives::Second);
        EXPECT_LT((exact.position - fast.position).norm(), 1e-11);
        // Each footpoint's chart point is the atlas's map of the footpoint into the chart of
        // its corner (the next projection starts there without mapping again).
        for (const PseudoManifold::Projection* q : {&reference, &plain, &fast}) {
          const ChartPoint mapped = b.pps->atlas().toChart(q->point, q->chartCorner);
          EXPECT_LT((mapped.p - q->chartPoint).norm(), 1e-13);
        }
        previous = plain;
      } else {
        previous = reference;
      }
      havePrevious = true;
    }
    // No evaluation at the start: fewer along the line than from the nearest samples.
    EXPECT_LT(nearbyEvaluations, sampleEvaluations);
  }
  // Stopping beyond a distance: a far point stops early with a distance above the bound; a point
  // within it converges as without the bound.
  SmoothProjectionOptions bounded;
  bounded.stopBeyond = 0.3;
  const Eigen::Vector3d far = 1.6 * Eigen::Vector3d(0.2, -0.5, 0.8).normalized();
  const PseudoManifold::Projection reference = fromNearestSample(far);
  ASSERT_GT(reference.distance, 0.5);
  const PseudoManifold::Projection stopped =
      b.pps->project(far, samples.nearest(far).first, bounded);
  EXPECT_TRUE(stopped.beyond);
  EXPECT_FALSE(stopped.converged);
  EXPECT_GT(stopped.distance, 0.3);
  const Eigen::Vector3d near = 1.1 * Eigen::Vector3d(0.2, -0.5, 0.8).normalized();
  const PseudoManifold::Projection inside =
      b.pps->project(near, samples.nearest(near).first, bounded);
  EXPECT_FALSE(inside.beyond);
  EXPECT_TRUE(inside.converged);
  EXPECT_NEAR(inside.distance, fromNearestSample(near).distance, 1e-13);
  // Written into an existing projection: every member as project() returns it, whatever the
  // projection held before (a stopped one without differential geometry, a converged one with a
  // cubic model); never over the projection it starts from.
  const auto expectSame = [](const PseudoManifold::Projection& a,
                             const PseudoManifold::Projection& e) {
    EXPECT_EQ(a.point.face, e.point.face);
    EXPECT_EQ(a.point.bary, e.point.bary);
    EXPECT_EQ(a.position, e.position);
    EXPECT_EQ(a.distance, e.distance);
    EXPECT_EQ(a.geometry.position, e.geometry.position);
    EXPECT_EQ(a.geometry.normal, e.geometry.normal);
    EXPECT_EQ(a.geometry.k1, e.geometry.k1);
    EXPECT_EQ(a.geometry.k2, e.geometry.k2);
    EXPECT_EQ(a.geometry.e1, e.geometry.e1);
    EXPECT_EQ(a.geometry.e2, e.geometry.e2);
    for (int i = 0; i < 2; ++i) EXPECT_EQ(a.derivatives.d[i], e.derivatives.d[i]);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(a.derivatives.dd[i], e.derivatives.dd[i]);
    EXPECT_EQ(a.chartCorner, e.chartCorner);
    EXPECT_EQ(a.chartPoint, e.chartPoint);
    ASSERT_EQ(a.firstStepMiss.has_value(), e.firstStepMiss.has_value());
    if (a.firstStepMiss) {
      EXPECT_EQ(a.firstStepMiss->p, e.firstStepMiss->p);
    }
    ASSERT_EQ(a.model.has_value(), e.model.has_value());
    if (a.model) {
      EXPECT_EQ(a.model->origin.p, e.model->origin.p);
      for (int i = 0; i < 4; ++i)
        EXPECT_EQ(a.model->derivatives.ddd[i], e.model->derivatives.ddd[i]);
    }
    EXPECT_EQ(a.iterations, e.iterations);
    EXPECT_EQ(a.converged, e.converged);
    EXPECT_EQ(a.beyond, e.beyond);
  };
  SmoothProjectionOptions cubic;
  cubic.cubicFinish = true;
  cubic.startFromModel = true;
  const PseudoManifold::Projection modeled =
      b.pps->project(near, samples.nearest(near).first, cubic);
  ASSERT_TRUE(modeled.model.has_value());
  const Eigen::Vector3d next = near + Eigen::Vector3d(0.01, -0.005, 0.008);
  const PseudoManifold::Projection returned = b.pps->project(next, modeled, cubic);
  EXPECT_TRUE(returned.converged);
  PseudoManifold::Projection written = stopped;
  b.pps->project(next, modeled, cubic, written);
  expectSame(written, returned);
  SmoothProjectionOptions cubicBounded = cubic;
  cubicBounded.stopBeyond = 0.05;
  const PseudoManifold::Projection returnedBeyond = b.pps->project(next, modeled, cubicBounded);
  EXPECT_TRUE(returnedBeyond.beyond);
  written = modeled;
  b.pps->project(next, modeled, cubicBounded, written);
  expectSame(written, returnedBeyond);
  EXPECT_THROW(b.pps->project(next, written, cubic, written), InputError);
  EXPECT_THROW(b.pps->project(Eigen::Vector3d(std::nan(""), 0.0, 0.0), reference), InputError);
  PseudoManifold::Projection broken = reference;
  broken.chartCorner = 3;
  EXPECT_THROW(b.pps->project(far, broken), InputError);
  broken = reference;
  broken.chartPoint.x() = std::nan("");
  EXPECT_THROW(b.pps->project(far, broken), InputError);
}

// The second-order start: along a line of equally spaced points, each projected from the one
// before with the miss of that one's first Newton step added to its own first step. The same
// footpoints as the projections from the nearest samples; the corrected first steps land much
// nearer their footpoints than the plain ones; a correction in another vertex's chart is not
// used.
TEST(PseudoManifold, SecondOrderStartFromTheNeighborsMiss) {
  const Built b = buildLoop(test::icosphere(1));
  const DenseSurfaceSamples samples(b);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.3, 1.0, 0.2).normalized();
  const Eigen::Vector3d across = direction.cross(Eigen::Vector3d::UnitX()).normalized();
  PseudoManifold::Projection plainPrevious, correctedPrevious;
  double plainMisses = 0.0, correctedMisses = 0.0;
  int corrections = 0;
  for (int i = 0; i < 16; ++i) {
    const Eigen::Vector3d x = 1.1 * direction + 0.02 * i * across;
    const PseudoManifold::Projection reference = b.pps->project(x, samples.nearest(x).first);
    ASSERT_TRUE(reference.converged);
    if (i == 0) {
      plainPrevious = correctedPrevious = reference;
      EXPECT_FALSE(reference.firstStepMiss.has_value());  // not started from a projection
      continue;
    }
    const PseudoManifold::Projection plain = b.pps->project(x, plainPrevious);
    SmoothProjectionOptions options;
    options.firstStepCorrection = correctedPrevious.firstStepMiss;
    const PseudoManifold::Projection corrected = b.pps->project(x, correctedPrevious, options);
    for (const PseudoManifold::Projection* q : {&plain, &corrected}) {
      EXPECT_TRUE(q->converged);
      EXPECT_LT((q->position - reference.position).norm(), 1e-11);
      EXPECT_NEAR(q->distance, reference.distance, 1e-13);
      EXPECT_NEAR(q->geometry.k1, reference.geometry.k1, 1e-9);
    }
    // How far the first steps end from the footpoints, from the third point on (the second
    // point's start has no correction yet), where the correction was used: the plain miss, and
    // what remains of it after the correction.
    if (i >= 2 && plain.firstStepMiss && corrected.firstStepMiss && options.firstStepCorrection &&
        options.firstStepCorrection->vertex == corrected.firstStepMiss->vertex) {
      plainMisses += plain.firstStepMiss->p.norm();
      correctedMisses += (corrected.firstStepMiss->p - options.firstStepCorrection->p).norm();
      ++corrections;
    }
    plainPrevious = plain;
    correctedPrevious = corrected;
  }
  ASSERT_GE(corrections, 8);
  EXPECT_LT(correctedMisses, 0.6 * plainMisses);
  // A correction given in the chart of another vertex is ignored: the first step is plain.
  const Eigen::Vector3d x = 1.1 * direction;
  const PseudoManifold::Projection start = b.pps->project(x, samples.nearest(x).first);
  const Eigen::Vector3d next = x + 0.02 * across;
  SmoothProjectionOptions elsewhere;
  const Index startVertex = b.mesh->from(3 * start.point.face + start.chartCorner);
  elsewhere.firstStepCorrection = ChartPoint{
      static_cast<Index>((startVertex + 1) % b.mesh->vertexCount()), Eigen::Vector2d(0.05, -0.05)};
  const PseudoManifold::Projection ignored = b.pps->project(next, start, elsewhere);
  const PseudoManifold::Projection plain = b.pps->project(next, start);
  EXPECT_EQ(ignored.iterations, plain.iterations);
  EXPECT_EQ(ignored.position, plain.position);
  EXPECT_EQ(ignored.firstStepMiss.has_value(), plain.firstStepMiss.has_value());
}

// The cubic finish and the start from the nearby projection's cubic model
// (SmoothProjectionOptions::cubicFinish, startFromModel, as the field projects its voxels) against
// the plain iteration (footpoints to 1e-12 of the chart radius, geometry evaluated there): lines
// of 30 points spaced like the voxels of a field (a thirtieth of an edge) within 4.5 spacings of
// the surface, each point projected from the one before (with the second-order start), stopped
// beyond three spacings; 6000 points on the mesh with vertex degrees 3 to 9.
TEST(PseudoManifold, CubicFinishAgreesWithThePlainIteration) {
  const Built b = buildLoop(test::mixedDegreeMesh());
  const HalfEdgeMesh& mesh = *b.mesh;
  const double spacing = 0.01;  // the mesh's edges are about 0.3 long, its radius 1
  const double band = 3.0 * spacing;
  SmoothProjectionOptions cubic;
  cubic.extrapolateLastStep = true;
  cubic.cubicFinish = true;
  cubic.startFromModel = true;
  cubic.stopBeyond = band;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double position = 0.0, distance = 0.0, normal = 0.0, curvature = 0.0, direction = 0.0;
  long plainEvaluations = 0, cubicEvaluations = 0;
  int points = 0, beyond = 0, withModel = 0;
  for (int line = 0; line < 200; ++line) {
    const auto face = static_cast<Index>(static_cast<std::size_t>(unit(random) * mesh.faceCount()) %
                                         mesh.faceCount());
    double u = unit(random), v = unit(random);
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    const FacePoint start{face, Eigen::Vector3d(1.0 - u - v, u, v)};
    const SmoothPoint surface = b.pps->evaluate(start, Derivatives::First);
    const Eigen::Vector3d tangent =
        surface.normal
            .cross(Eigen::Vector3d(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5))
            .normalized();
    const Eigen::Vector3d origin =
        surface.position + (9.0 * unit(random) - 4.5) * spacing * surface.normal;
    PseudoManifold::Projection previousPlain, previousCubic;
    for (int i = 0; i < 30; ++i) {
      const Eigen::Vector3d x = origin + i * spacing * tangent;
      PseudoManifold::Projection a, c;
      if (i == 0) {
        a = b.pps->project(x, start);
        c = b.pps->project(x, start, cubic);
      } else {
        SmoothProjectionOptions plainStep, cubicStep = cubic;
        if (i >= 2) {
          plainStep.firstStepCorrection = previousPlain.firstStepMiss;
          cubicStep.firstStepCorrection = previousCubic.firstStepMiss;
        }
        withModel += previousCubic.model.has_value() ? 1 : 0;
        a = b.pps->project(x, previousPlain, plainStep);
        c = b.pps->project(x, previousCubic, cubicStep);
      }
      ASSERT_TRUE(a.converged);
      plainEvaluations += a.iterations;
      cubicEvaluations += c.iterations;
      ++points;
      if (c.beyond) {
        // Stopped: certainly beyond the band.
        EXPECT_GT(a.distance, band);
        ++beyond;
      } else {
        ASSERT_TRUE(c.converged);
        position = std::max(position, (a.position - c.position).norm());
        distance = std::max(distance, std::abs(a.distance - c.distance));
        normal = std::max(normal, angleBetween(a.geometry.normal, c.geometry.normal));
        const double scale = std::max({std::abs(a.geometry.k1), std::abs(a.geometry.k2), 1.0});
        curvature = std::max({curvature, std::abs(a.geometry.k1 - c.geometry.k1) / scale,
                              std::abs(a.geometry.k2 - c.geometry.k2) / scale});
        if (a.geometry.k1 - a.geometry.k2 > 0.05 * scale) {
          direction = std::max(direction,
                               std::asin(std::min(1.0, a.geometry.e1.cross(c.geometry.e1).norm())));
        }
      }
      if (a.distance < band) {
        EXPECT_FALSE(c.beyond);
      }
      previousPlain = std::move(a);
      previousCubic = std::move(c);
    }
  }
  std::printf(
      "cubic finish against the plain iteration at %d points (%d stopped beyond the band, "
      "%d started from a model): positions %.3g, distances %.3g, normals %.3g rad, "
      "curvatures %.3g of max(|k|, 1), e1 %.3g rad; surface evaluations %ld instead of "
      "%ld\n",
      points, beyond, withModel, position, distance, normal, curvature, direction, cubicEvaluations,
      plainEvaluations);
  EXPECT_GT(beyond, 500);
  EXPECT_GT(withModel, 3000);
  EXPECT_LT(position, 1e-9);
  EXPECT_LT(distance, 1e-11);
  EXPECT_LT(normal, 1e-8);
  EXPECT_LT(curvature, 5e-5);
  EXPECT_LT(direction, 1e-4);
  EXPECT_LT(cubicEvaluations, 0.4 * plainEvaluations);
}

TEST(PseudoManifold, RefusesBadOptions) {
  const auto mesh = test::octahedron().build();
  const LoopLimitSurface loop(mesh);
  PseudoManifoldOptions options;
  options.maxBidegree = 1;
  EXPECT_THROW(PseudoManifold(loop, options), InputError);
  options.maxBidegree = 7;
  options.samplesPerControl = 1;
  EXPECT_THROW(PseudoManifold(loop, options), InputError);
  options.samplesPerControl = 2;
  options.maxBytes = 1000;  // 6 vertices x 36 control points x 24 bytes = 5184
  EXPECT_THROW(PseudoManifold(loop, options), InputError);
  const PseudoManifold pps(loop);
  EXPECT_THROW(pps.evaluate({99, Eigen::Vector3d(1, 0, 0)}, Derivatives::None), InputError);
  EXPECT_THROW(pps.chartDerivatives({0, Eigen::Vector3d(0, 0.5, 0.5)}, 0), InputError);
}

}  // namespace
}  // namespace d2vdb
