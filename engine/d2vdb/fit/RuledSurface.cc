#include "d2vdb/fit/RuledSurface.h"

#include <string>

#include "d2vdb/core/Error.h"

namespace d2vdb {

std::vector<Ruling> surfaceRulings(const BSplineSurface& surface, int samplesPerSpan) {
  if (surface.degreeU() != 1) {
    throw InputError("rulings need a surface of degree 1 in u (a ruled surface, --ruled), not " +
                     std::to_string(surface.degreeU()));
  }
  if (samplesPerSpan < 0) throw InputError("ruling samples per span must not be negative");
  const std::vector<double> breaksU = surface.knotsU().breakpoints();
  const std::vector<double> breaksV = surface.knotsV().breakpoints();
  std::vector<double> vs;
  for (std::size_t s = 0; s + 1 < breaksV.size(); ++s) {
    const ParameterInterval span{breaksV[s], breaksV[s + 1]};
    vs.push_back(span.start);
    for (int i = 1; i <= samplesPerSpan; ++i)
      vs.push_back(span.at(double(i) / (samplesPerSpan + 1)));
  }
  if (!surface.isClosedV()) vs.push_back(breaksV.back());
  std::vector<Ruling> rulings;
  for (const double v : vs) {
    for (std::size_t piece = 0; piece + 1 < breaksU.size(); ++piece) {
      rulings.push_back({v, static_cast<int>(piece), surface.evaluate(breaksU[piece], v),
                         surface.evaluate(breaksU[piece + 1], v)});
    }
  }
  return rulings;
}

double surfaceRulingCount(const BSplineSurface& surface, int samplesPerSpan) {
  const double spansU = static_cast<double>(surface.knotsU().breakpoints().size()) - 1.0;
  const double spansV = static_cast<double>(surface.knotsV().breakpoints().size()) - 1.0;
  return (spansV * (samplesPerSpan + 1.0) + (surface.isClosedV() ? 0.0 : 1.0)) * spansU;
}

}  // namespace d2vdb
