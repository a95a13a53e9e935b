#include "d2vdb/support/SupportCheck.h"

#include <utility>

#include "d2vdb/core/Error.h"
#include "d2vdb/core/NumberFormat.h"

namespace d2vdb {
namespace {

// Why a mesh's Gauss map is not injective, when some of its triangles keep and some reverse their
// orientation on the sphere; empty otherwise.
std::string gaussImageReason(const std::optional<MeshGaussImage>& image) {
  if (!image || image->reversingTriangles == 0 || image->preservingTriangles == 0) return {};
  return "Of its " +
         std::to_string(image->preservingTriangles + image->reversingTriangles +
                        image->collapsedTriangles) +
         " triangles, " + std::to_string(image->reversingTriangles) +
         " have a saddle-shaped (orientation-reversing) Gauss image and " +
         std::to_string(image->preservingTriangles) +
         " a convex one, so its Gauss map is not injective. ";
}

}  // namespace

SphericalTriangulation validityDomain(const SupportFunction& h,
                                      const std::optional<SphericalTriangulation>& patch) {
  return patch ? *patch : validationSphere(h.degree());
}

DomainSupportFit fitSupportOverDomain(const OrientedSamples& samples, bool overPatch, int degree,
                                      double regularization, const std::string& sourceName) {
  SupportFitOptions options;
  options.degree = degree;
  options.regularization = regularization >= 0.0 ? regularization
                           : overPatch           ? kPatchSupportRegularization
                                                 : kDefaultSupportRegularization;
  DomainSupportFit fit;
  fit.function = fitSupportFunction(samples, options, &fit.report, sourceName);
  if (fit.report.renormalizedNormals > 0) {
    fit.warnings.push_back(std::to_string(fit.report.renormalizedNormals) +
                           " sample normals were not unit length (off by up to " +
                           formatNumber(fit.report.largestNormalDeviation, 6) +
                           ") and were normalised");
  }
  return fit;
}

SupportCheck checkSupportFunction(const SupportFunction& h,
                                  const std::optional<SphericalTriangulation>& patch,
                                  const std::optional<SupportFitReport>& fit,
                                  const std::optional<MeshGaussImage>& gaussImage,
                                  const std::string& sourceName, bool allowSingular) {
  SupportCheck check;
  check.validity = analyzeSupportValidity(h, validityDomain(h, patch));
  const double relativeResidual = fit && fit->size > 0.0 ? fit->maxResidual / fit->size : 0.0;
  const bool missed = relativeResidual > kMaxRelativeSupportResidual;
  if (check.validity.regular() && !missed) return check;
  std::string why =
      sourceName + ": the support function is " + check.validity.describe() +
      (missed ? " but misses the samples by up to " + formatNumber(fit->maxResidual, 4) + " (" +
                    formatNumber(100.0 * relativeResidual, 3) + "% of the size, more than " +
                    formatNumber(100.0 * kMaxRelativeSupportResidual, 3) + "%)"
              : std::string()) +
      ". ";
  why += gaussImageReason(gaussImage);
  why += patch ? "A patch has a support function only where its Gauss map is injective (all "
                 "convex or all saddle-shaped, no fold)"
               : "A closed surface has a support function only if it is convex (its Gauss map "
                 "is then injective)";
  why +=
      "; pass --patches to split it into patches of one curvature sign, each fitted over its "
      "own Gauss image, or offset it with --method levelset";
  if (!allowSingular) throw InputError(why + ", or pass --allow-singular to keep this result");
  check.warnings.push_back(why + " (kept: --allow-singular)");
  return check;
}

}  // namespace d2vdb
