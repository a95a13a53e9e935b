// The convergence plot (SVG) shared by fit-curve and fit-surface.
#pragma once

#include <string>
#include <vector>

#include "d2vdb/fit/CurveFit.h"
#include "d2vdb/fit/FitMethod.h"

namespace d2vdb::cli {

/// One fit's history for the plot.
struct ConvergenceSeries {
  FitMethod method = FitMethod::SDM;
  const std::vector<FitIteration>* history = nullptr;  ///< must outlive the call
  int iterations = 0;
  FitStatus status = FitStatus::IterationCap;
};

/// Writes the RMS distance per iteration of every series on a log scale as SVG, atomically;
/// `command` names the sub-command in a comment. RuntimeFailure when the file cannot be written.
void writeConvergencePlot(const std::string& file, const std::vector<ConvergenceSeries>& runs,
                          const std::string& command);

}  // namespace d2vdb::cli
