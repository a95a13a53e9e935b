// The fitting methods of the squared-distance-minimisation fitters (engine/README.md, "The
// squared-distance approximant").
#pragma once

#include <cstdint>
#include <string>

#include "d2vdb/field/Approximant.h"

namespace d2vdb {

/// Which error term each sensor contributes to the quadratic model of one iteration.
enum class FitMethod : std::uint8_t {
  PDM = 0,         ///< point distance |x - s|^2: linear convergence
  TDM = 1,         ///< tangent distance: Gauss-Newton, with Levenberg-Marquardt damping
  SDM = 2,         ///< squared distance (curvature-aware, clamped): Newton-like
  TDMPlusPDM = 3,  ///< TDM + pdmWeight * PDM (TDM regularised by a PDM term)
};

/// "pdm", "tdm", "sdm" or "tdm+pdm".
const char* fitMethodName(FitMethod method);

/// Parses a name as fitMethodName() writes it (case-insensitive). Throws InputError naming the
/// accepted names for anything else.
FitMethod parseFitMethod(const std::string& name);

/// The quadratic form one sensor contributes under `method`: approximant.form(PDM / TDM / SDM), or
/// for TDMPlusPDM the TDM form plus pdmWeight times the PDM form (same footpoint). World units.
QuadraticForm fitForm(const Approximant& approximant, FitMethod method, double pdmWeight);

}  // namespace d2vdb
