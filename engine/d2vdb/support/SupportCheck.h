// Whether a support function represents the surface it comes from: fitted over the domain of its
// input (the whole sphere, or a patch's Gauss image), regular there, and close to its samples.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "d2vdb/support/SphericalTriangulation.h"
#include "d2vdb/support/SupportFit.h"
#include "d2vdb/support/SupportFunction.h"
#include "d2vdb/support/SupportSamples.h"
#include "d2vdb/support/SupportValidity.h"

namespace d2vdb {

/// A fit whose max residual exceeds this fraction of its samples' bounding-box diagonal is refused
/// like a singular one: the input is not one support-function surface (a regular fit can still
/// miss badly, e.g. a torus over the whole sphere averages its outer and inner halves into one
/// convex surface).
inline constexpr double kMaxRelativeSupportResidual = 0.02;

/// The domain the validity of `h` is analysed over: `patch` (the Gauss image it was fitted over)
/// when given, else validationSphere(h.degree()).
SphericalTriangulation validityDomain(const SupportFunction& h,
                                      const std::optional<SphericalTriangulation>& patch);

/// A fit by fitSupportOverDomain().
struct DomainSupportFit {
  SupportFunction function;
  SupportFitReport report;
  std::vector<std::string> warnings;  ///< sample normals that were not of unit length
};

/// fitSupportFunction() of `samples` at `degree` for a function over the whole sphere (`overPatch`
/// false) or over a patch's Gauss image (true): `regularization` < 0 takes that domain's default,
/// kDefaultSupportRegularization or kPatchSupportRegularization. A warning says how many normals
/// were normalised and by how much they were off. Throws InputError as fitSupportFunction()
/// (naming `sourceName`, e.g. "'bunny.obj'").
DomainSupportFit fitSupportOverDomain(const OrientedSamples& samples, bool overPatch, int degree,
                                      double regularization, const std::string& sourceName);

/// What checkSupportFunction() found.
struct SupportCheck {
  SupportValidity validity;           ///< over validityDomain()
  std::vector<std::string> warnings;  ///< the problem, when it was kept (allowSingular)
};

/// Analyses the validity of `h` over validityDomain(h, patch) and whether `h` represents its input:
/// it must be regular there, and `fit` (present when `h` was fitted to samples) must not miss them
/// by more than kMaxRelativeSupportResidual of their size. Otherwise throws InputError that starts
/// with `sourceName` (e.g. "'torus.obj'"), says what is wrong (with the orientation counts of
/// `gaussImage` when the input was a mesh whose Gauss map is not injective) and what to do (in
/// the terms of the d2vdb command: --patches, --method levelset, --allow-singular); with
/// `allowSingular` the same explanation becomes a warning of the result instead.
SupportCheck checkSupportFunction(const SupportFunction& h,
                                  const std::optional<SphericalTriangulation>& patch,
                                  const std::optional<SupportFitReport>& fit,
                                  const std::optional<MeshGaussImage>& gaussImage,
                                  const std::string& sourceName, bool allowSingular);

}  // namespace d2vdb
