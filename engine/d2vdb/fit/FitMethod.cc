#include "d2vdb/fit/FitMethod.h"

#include <algorithm>
#include <cctype>

#include "d2vdb/core/Error.h"

namespace d2vdb {

const char* fitMethodName(FitMethod method) {
  switch (method) {
    case FitMethod::PDM:
      return "pdm";
    case FitMethod::TDM:
      return "tdm";
    case FitMethod::SDM:
      return "sdm";
    case FitMethod::TDMPlusPDM:
      return "tdm+pdm";
  }
  return "unknown";
}

FitMethod parseFitMethod(const std::string& name) {
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const FitMethod method :
       {FitMethod::PDM, FitMethod::TDM, FitMethod::SDM, FitMethod::TDMPlusPDM}) {
    if (lower == fitMethodName(method)) return method;
  }
  throw InputError("unknown fitting method '" + name + "'; use one of pdm, tdm, sdm, tdm+pdm");
}

QuadraticForm fitForm(const Approximant& approximant, FitMethod method, double pdmWeight) {
  switch (method) {
    case FitMethod::PDM:
      return approximant.form(ErrorTerm::PDM);
    case FitMethod::TDM:
      return approximant.form(ErrorTerm::TDM);
    case FitMethod::SDM:
      return approximant.form(ErrorTerm::SDM);
    case FitMethod::TDMPlusPDM:
      break;
  }
  QuadraticForm form = approximant.form(ErrorTerm::TDM);
  form.A += pdmWeight * Eigen::Matrix3d::Identity();
  form.b = form.A * approximant.footpoint;
  form.c = approximant.footpoint.dot(form.b);
  return form;
}

}  // namespace d2vdb
