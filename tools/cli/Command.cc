#include "Command.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <mutex>

namespace d2vdb::cli {

void status(const GlobalOptions& options, std::string_view message) {
  if (!options.quiet) std::cerr << message << '\n';
}

void warning(std::string_view message) {
  std::cerr << "warning: " << message << '\n';
}

ProgressCallback makeProgressPrinter(const GlobalOptions& options) {
  if (options.quiet) return {};
  struct State {
    std::mutex mutex;
    Stopwatch clock;
    std::string stage;
    int lastPercent = -1;
    bool visible = false;
    bool terminal = ::isatty(STDERR_FILENO) != 0;
  };
  auto state = std::make_shared<State>();
  return [state](std::string_view stage, double fraction) {
    const std::lock_guard<std::mutex> lock(state->mutex);
    // Steps shorter than a second stay silent, their completion included.
    if (!state->visible && state->clock.seconds() < 1.0) return;
    const int percent = static_cast<int>(std::floor(100.0 * std::clamp(fraction, 0.0, 1.0)));
    const bool newStage = stage != state->stage;
    // Without a terminal, print one line per 10% so logs stay short.
    const int step = state->terminal ? 1 : 10;
    if (!newStage && percent / step == state->lastPercent / step) return;
    if (newStage && state->visible && state->terminal) std::cerr << '\n';
    state->stage = std::string(stage);
    state->lastPercent = percent;
    state->visible = true;
    if (state->terminal) {
      std::cerr << '\r' << stage << ": " << percent << "%" << (percent >= 100 ? "\n" : "")
                << std::flush;
      if (percent >= 100) state->visible = false;
    } else {
      std::cerr << stage << ": " << percent << "%\n";
    }
  };
}

void printJson(const nlohmann::json& report) {
  std::cout << report.dump(2) << std::endl;
}

CLI::Option* addVector3Option(CLI::App& app, const std::string& name, std::array<double, 3>& value,
                              const std::string& description) {
  return app
      .add_option_function<std::vector<double>>(
          name,
          [&value, name](const std::vector<double>& numbers) {
            if (numbers.size() != 3) {
              throw CLI::ValidationError(name, "needs exactly three numbers, e.g. 0,0,0");
            }
            for (const double number : numbers) {
              if (!std::isfinite(number)) {
                throw CLI::ValidationError(name, "numbers must be finite");
              }
            }
            std::copy(numbers.begin(), numbers.end(), value.begin());
          },
          description)
      ->delimiter(',')
      ->expected(1, 3)
      ->type_name("X,Y,Z");
}

}  // namespace d2vdb::cli
