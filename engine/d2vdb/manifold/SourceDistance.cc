#include "d2vdb/manifold/SourceDistance.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "d2vdb/core/Error.h"

namespace d2vdb {

using Index = HalfEdgeMesh::Index;

namespace {

/// Moves `point` by the barycentric displacement `delta` (components summing to 0), crossing
/// edges into neighbouring faces; the displacement left at an edge continues in the neighbour's
/// coordinates with the two canonical triangles unfolded about the edge.
FacePoint walk(const HalfEdgeMesh& mesh, FacePoint point, Eigen::Vector3d delta) {
  for (int crossing = 0; crossing < 64; ++crossing) {
    double t = 1.0;
    int exit = -1;
    for (int i = 0; i < 3; ++i) {
      if (delta[i] < 0.0) {
        const double reach = -point.bary[i] / delta[i];
        if (reach < t) {
          t = reach;
          exit = i;
        }
      }
    }
    if (exit < 0) {
      point.bary += delta;
      point.bary = point.bary.cwiseMax(0.0);
      point.bary /= point.bary.sum();
      return point;
    }
    t = std::max(t, 0.0);
    point.bary += t * delta;
    point.bary[exit] = 0.0;
    point.bary = point.bary.cwiseMax(0.0);
    point.bary /= point.bary.sum();
    delta *= 1.0 - t;
    const int p = (exit + 1) % 3;
    const int q = (exit + 2) % 3;
    const Index across = mesh.twin(3 * point.face + static_cast<Index>(p));  // Q -> P
    const int cq = static_cast<int>(across % 3);
    const int cp = (cq + 1) % 3;
    const int co = (cq + 2) % 3;
    FacePoint next;
    next.face = HalfEdgeMesh::face(across);
    next.bary[cp] = point.bary[p];
    next.bary[cq] = point.bary[q];
    next.bary[co] = 0.0;
    Eigen::Vector3d nextDelta;
    nextDelta[cp] = delta[p] + delta[exit];
    nextDelta[cq] = delta[q] + delta[exit];
    nextDelta[co] = -delta[exit];
    point = next;
    delta = nextDelta;
  }
  return point;
}

}  // namespace

std::vector<Eigen::Vector3d> faceLattice(int samplesPerEdge) {
  std::vector<Eigen::Vector3d> points;
  const double s = samplesPerEdge;
  for (int i = 0; i <= samplesPerEdge; ++i) {
    for (int j = 0; i + j <= samplesPerEdge; ++j) {
      points.emplace_back((samplesPerEdge - i - j) / s, i / s, j / s);
    }
  }
  return points;
}

SourceProjection projectOntoSource(const SourceSurface& source, const Eigen::Vector3d& x,
                                   const FacePoint& start) {
  if (!x.allFinite()) throw InputError("cannot project a non-finite point");
  const HalfEdgeMesh& mesh = source.mesh();
  if (start.face >= mesh.faceCount()) {
    throw InputError("face " + std::to_string(start.face) + " does not exist");
  }
  FacePoint point = start;
  SourceJet jet = source.evaluate(point);
  SourceProjection best{point, jet.position, (jet.position - x).norm()};
  if (!jet.derivativesValid) {
    // An extraordinary vertex: no derivative of the face parametrisation; start just inside.
    point.bary = (1.0 - 3e-7) * point.bary + Eigen::Vector3d::Constant(1e-7);
    jet = source.evaluate(point);
  }
  double value = (jet.position - x).squaredNorm();
  for (int iteration = 0; iteration < 40 && jet.derivativesValid; ++iteration) {
    const Eigen::Vector3d residual = jet.position - x;
    Eigen::Matrix2d jtj;
    jtj << jet.d1.dot(jet.d1), jet.d1.dot(jet.d2), jet.d1.dot(jet.d2), jet.d2.dot(jet.d2);
    const Eigen::Vector2d gradient(jet.d1.dot(residual), jet.d2.dot(residual));
    const Eigen::LDLT<Eigen::Matrix2d> solver(jtj);
    if (solver.info() != Eigen::Success) break;
    Eigen::Vector2d step = -solver.solve(gradient);
    if (!step.allFinite()) break;
    const double longest = 0.5;  // at most half a face per step
    if (step.norm() > longest) step *= longest / step.norm();
    bool accepted = false;
    for (int halving = 0; halving < 30; ++halving) {
      const FacePoint candidate =
          walk(mesh, point, Eigen::Vector3d(-step[0] - step[1], step[0], step[1]));
      const SourceJet candidateJet = source.evaluate(candidate);
      const double candidateValue = (candidateJet.position - x).squaredNorm();
      if (candidateValue < value && candidateJet.derivativesValid) {
        point = candidate;
        jet = candidateJet;
        value = candidateValue;
        accepted = true;
        break;
      }
      step *= 0.5;
    }
    if (!accepted || step.norm() < 1e-14) break;
  }
  if (std::sqrt(value) < best.distance) best = {point, jet.position, std::sqrt(value)};
  return best;
}

SourceDistanceStatistics distanceToSource(const PseudoManifold& surface,
                                          const SourceSurface& source, int samplesPerEdge,
                                          int faceStep) {
  if (&surface.mesh() != &source.mesh()) {
    throw InputError("the smooth surface and the source surface have different meshes");
  }
  if (samplesPerEdge < 1) throw InputError("at least one sample interval per edge is needed");
  if (faceStep < 1) throw InputError("the face step must be at least 1");
  const HalfEdgeMesh& mesh = source.mesh();
  const std::vector<Eigen::Vector3d> lattice = faceLattice(samplesPerEdge);
  struct FaceResult {
    double maxDistance = 0.0;
    double sumSquares = 0.0;
    double maxParametric = 0.0;
    double sumParametric = 0.0;
  };
  const std::size_t faces = (mesh.faceCount() + faceStep - 1) / faceStep;
  std::vector<FaceResult> results(faces);
  tbb::parallel_for(std::size_t{0}, faces, [&](std::size_t f) {
    const auto face = static_cast<Index>(f * static_cast<std::size_t>(faceStep));
    std::vector<Eigen::Vector3d> sourcePoints(lattice.size());
    source.positions(face, lattice.data(), lattice.size(), sourcePoints.data());
    FaceResult& result = results[f];
    for (std::size_t i = 0; i < lattice.size(); ++i) {
      const FacePoint point{face, lattice[i]};
      const Eigen::Vector3d x = surface.position(point);
      const double parametric = (x - sourcePoints[i]).norm();
      const double distance = std::min(parametric, projectOntoSource(source, x, point).distance);
      result.maxDistance = std::max(result.maxDistance, distance);
      result.sumSquares += distance * distance;
      result.maxParametric = std::max(result.maxParametric, parametric);
      result.sumParametric += parametric * parametric;
    }
  });
  SourceDistanceStatistics statistics;
  double sumSquares = 0.0;
  double sumParametric = 0.0;
  for (const FaceResult& r : results) {
    statistics.maxDistance = std::max(statistics.maxDistance, r.maxDistance);
    statistics.maxParametric = std::max(statistics.maxParametric, r.maxParametric);
    sumSquares += r.sumSquares;
    sumParametric += r.sumParametric;
  }
  statistics.samples = lattice.size() * faces;
  statistics.rmsDistance = std::sqrt(sumSquares / static_cast<double>(statistics.samples));
  statistics.rmsParametric = std::sqrt(sumParametric / static_cast<double>(statistics.samples));
  statistics.diagonal = mesh.boundingBoxDiagonal();
  return statistics;
}

MeshDeviationStatistics distanceToMesh(const PseudoManifold& surface, const MeshDistance& mesh,
                                       int samplesPerEdge, int faceStep) {
  if (samplesPerEdge < 1) throw InputError("at least one sample interval per edge is needed");
  if (faceStep < 1) throw InputError("the face step must be at least 1");
  const std::vector<Eigen::Vector3d> lattice = faceLattice(samplesPerEdge);
  const std::size_t faces = (surface.mesh().faceCount() + faceStep - 1) / faceStep;
  std::vector<double> maxima(faces, 0.0);
  std::vector<double> sumSquares(faces, 0.0);
  tbb::parallel_for(std::size_t{0}, faces, [&](std::size_t f) {
    const auto face = static_cast<Index>(f * static_cast<std::size_t>(faceStep));
    for (const Eigen::Vector3d& barycentric : lattice) {
      const double distance =
          mesh.closestPoint(surface.position(FacePoint{face, barycentric})).distance;
      maxima[f] = std::max(maxima[f], distance);
      sumSquares[f] += distance * distance;
    }
  });
  MeshDeviationStatistics statistics;
  double sum = 0.0;
  for (std::size_t f = 0; f < faces; ++f) {
    statistics.maxDistance = std::max(statistics.maxDistance, maxima[f]);
    sum += sumSquares[f];
  }
  statistics.samples = lattice.size() * faces;
  statistics.rmsDistance =
      statistics.samples > 0 ? std::sqrt(sum / static_cast<double>(statistics.samples)) : 0.0;
  return statistics;
}

}  // namespace d2vdb
