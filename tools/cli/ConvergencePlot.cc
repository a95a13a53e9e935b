// The convergence plot of the fitting commands (ConvergencePlot.h).
#include "ConvergencePlot.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>

#include "d2vdb/core/AtomicFile.h"

namespace d2vdb::cli {

void writeConvergencePlot(const std::string& file, const std::vector<ConvergenceSeries>& runs,
                          const std::string& command) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = 0.0;
  int maxIteration = 1;
  for (const ConvergenceSeries& run : runs) {
    for (const FitIteration& row : *run.history) {
      if (row.rmsDistance > 0.0) {
        lo = std::min(lo, row.rmsDistance);
        hi = std::max(hi, row.rmsDistance);
      }
    }
    maxIteration = std::max(maxIteration, run.iterations);
  }
  if (!(hi > 0.0)) lo = hi = 1.0;
  const double top = std::ceil(std::log10(hi) + 1e-12);
  double bottom = std::floor(std::log10(lo));
  if (bottom >= top) bottom = top - 1.0;
  const double width = 640.0, height = 420.0, left = 70.0, right = 20.0, upper = 20.0, lower = 50.0;
  const auto px = [&](double iteration) {
    return left + (width - left - right) * iteration / maxIteration;
  };
  const auto py = [&](double value) {
    return upper + (height - upper - lower) * (top - std::log10(value)) / (top - bottom);
  };
  const char* colours[] = {"#b3261e", "#1f4e9c", "#2e7d32", "#6a1b9a"};
  writeStreamAtomically(file, [&](std::ostream& out) {
    out.precision(9);
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << width << ' ' << height
        << "\" width=\"" << width << "\" height=\"" << height << "\" font-family=\"sans-serif\" "
        << "font-size=\"12\">\n"
        << "  <!-- d2vdb " << command << ": RMS distance per iteration, log scale -->\n"
        << "  <rect x=\"" << left << "\" y=\"" << upper << "\" width=\"" << width - left - right
        << "\" height=\"" << height - upper - lower << "\" fill=\"none\" stroke=\"black\"/>\n";
    for (double decade = bottom; decade <= top + 1e-9; decade += 1.0) {
      const double yy = py(std::pow(10.0, decade));
      out << "  <line x1=\"" << left << "\" y1=\"" << yy << "\" x2=\"" << width - right
          << "\" y2=\"" << yy << "\" stroke=\"#dddddd\"/>\n"
          << "  <text x=\"" << left - 6 << "\" y=\"" << yy + 4 << "\" text-anchor=\"end\">1e"
          << static_cast<int>(decade) << "</text>\n";
    }
    out << "  <text x=\"" << (left + width - right) / 2 << "\" y=\"" << height - 12
        << "\" text-anchor=\"middle\">iteration (0.." << maxIteration << ")</text>\n"
        << "  <text x=\"16\" y=\"" << (upper + height - lower) / 2
        << "\" transform=\"rotate(-90 16 " << (upper + height - lower) / 2
        << ")\" text-anchor=\"middle\">RMS distance</text>\n";
    int series = 0;
    for (const ConvergenceSeries& run : runs) {
      const char* colour = colours[series % 4];
      out << "  <polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\" points=\"";
      for (const FitIteration& row : *run.history) {
        if (row.rmsDistance > 0.0) out << px(row.iteration) << ',' << py(row.rmsDistance) << ' ';
      }
      out << "\"/>\n"
          << "  <text x=\"" << width - right - 10 << "\" y=\"" << upper + 20 + 16 * series
          << "\" text-anchor=\"end\" fill=\"" << colour << "\">" << fitMethodName(run.method)
          << " (" << run.iterations << " iterations, " << fitStatusName(run.status) << ")</text>\n";
      ++series;
    }
    out << "</svg>\n";
  });
}

}  // namespace d2vdb::cli
