#include "d2vdb/core/ResourceBudget.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "d2vdb/core/Error.h"

namespace d2vdb {
namespace {

void enforce(const BudgetRequest& request, std::uint64_t limit, const std::string& what,
             const std::string& budgetName, const std::string& option) {
  if (limit == 0 || request.estimatedBytes <= static_cast<double>(limit)) return;
  std::string message = request.subject + " would need about " +
                        byteSizeText(request.estimatedBytes) + " " + what + ", above the " +
                        budgetName + " budget of " + byteSizeText(static_cast<double>(limit)) +
                        " (" + option + "); ";
  message += request.remedy.empty() ? "raise " + option : request.remedy + ", or raise " + option;
  throw InputError(message);
}

}  // namespace

void enforceMemoryBudget(const BudgetRequest& request, const ResourceBudget& budget) {
  enforce(request, budget.maxMemoryBytes, "of memory", "memory", "--max-memory");
}

void enforceOutputBudget(const BudgetRequest& request, const ResourceBudget& budget) {
  enforce(request, budget.maxOutputBytes, "of output files", "output", "--max-output");
}

std::string byteSizeText(double bytes) {
  if (!std::isfinite(bytes) || bytes > 1e30) return "inf";
  static const char* const kUnits[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int unit = 0;
  while (bytes >= 999.5 && unit < 6) {
    bytes /= 1000.0;
    ++unit;
  }
  std::ostringstream text;
  text.precision(unit == 0 ? 4 : 3);
  text << bytes << ' ' << kUnits[unit];
  return text.str();
}

std::uint64_t parseByteSize(const std::string& text, const std::string& option) {
  const auto refuse = [&]() {
    throw InputError(option +
                     ": expected a byte count such as 16G, 512MiB or 1e9 (0 = no limit), "
                     "got '" +
                     text + "'");
  };
  const char* begin = text.c_str();
  char* end = nullptr;
  const double number = std::strtod(begin, &end);
  if (end == begin || !std::isfinite(number) || number < 0.0) refuse();
  std::string unit(end);
  for (char& c : unit) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  double scale = 1.0;
  if (unit.empty() || unit == "b") {
    scale = 1.0;
  } else {
    const std::string prefixes = "kmgt";
    const std::size_t power = prefixes.find(unit[0]);
    const std::string rest = unit.substr(1);
    if (power == std::string::npos) refuse();
    if (rest.empty() || rest == "b") {
      scale = std::pow(1000.0, static_cast<double>(power + 1));
    } else if (rest == "ib") {
      scale = std::pow(1024.0, static_cast<double>(power + 1));
    } else {
      refuse();
    }
  }
  const double bytes = number * scale;
  if (!(bytes < 18446744073709551615.0)) refuse();
  return static_cast<std::uint64_t>(bytes);
}

long long largestFitting(long long low, long long high,
                         const std::function<bool(long long)>& fits) {
  if (low > high || !fits(low)) return low - 1;
  if (fits(high)) return high;
  long long good = low, bad = high;  // fits(good), !fits(bad)
  while (bad - good > 1) {
    const long long middle = good + (bad - good) / 2;
    (fits(middle) ? good : bad) = middle;
  }
  return good;
}

}  // namespace d2vdb
