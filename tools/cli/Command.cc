#include "Command.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <sstream>

#include "d2vdb/core/Error.h"

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
    Stopwatch clock;           // since the printer was made: nothing shows in the first second
    std::string stage;         // the stage last reported
    int percent = -1;          // the highest percentage reported for it
    bool shown = false;        // a line of this stage was printed
    bool lineOpen = false;     // terminal: the stage's line waits for its end
    double lastPrint = -1e30;  // clock.seconds() of the last line printed
    bool terminal = ::isatty(STDERR_FILENO) != 0;
  };
  // A terminal redraws the stage's one line at most ten times a second; a log gets a line when
  // a stage shows, then at most one every ten seconds, and its end.
  constexpr double kTerminalInterval = 0.1, kLogInterval = 10.0;
  auto state = std::make_shared<State>();
  return [state](std::string_view stage, double fraction) {
    const std::lock_guard<std::mutex> lock(state->mutex);
    if (stage != state->stage) {
      if (state->lineOpen) std::cerr << '\n';
      state->stage = std::string(stage);
      state->percent = -1;
      state->shown = state->lineOpen = false;
    }
    // Within a stage the percentage never goes back.
    const int percent = std::max(
        state->percent, static_cast<int>(std::floor(100.0 * std::clamp(fraction, 0.0, 1.0))));
    if (percent == state->percent) return;
    state->percent = percent;
    const double now = state->clock.seconds();
    if (now < 1.0) return;  // steps shorter than a second stay silent, their end included
    const bool done = percent >= 100;
    const double interval = state->terminal ? kTerminalInterval : kLogInterval;
    if (state->shown && !done && now - state->lastPrint < interval) return;
    state->lastPrint = now;
    state->shown = true;
    if (state->terminal) {
      std::cerr << '\r' << stage << ": " << percent << '%' << (done ? "\n" : "") << std::flush;
      state->lineOpen = !done;
    } else {
      std::cerr << stage << ": " << percent << "%\n";
    }
  };
}

void printReport(const Report& report, const GlobalOptions& options) {
  if (options.json) {
    printJson(report.json);
  } else if (report.textKind == Report::Text::Answer) {
    std::cout << report.text << std::flush;
  } else if (!options.quiet) {
    std::cerr << report.text;
  }
}

void CommandContext::status(std::string_view message) const {
  cli::status(options_, message);
}

ProgressCallback CommandContext::progress() const {
  return progress_;
}

const CommandRegistry::Entry* CommandRegistry::chosen() const {
  for (const Entry& entry : entries_) {
    if (entry.command->parsed()) return &entry;
  }
  return nullptr;
}

int CommandRegistry::run() const {
  const Entry* entry = chosen();
  if (entry == nullptr) {
    std::cerr << "error: no sub-command given; run 'd2vdb --help'\n";
    return kUsageError;
  }
  const Report report = entry->run(CommandContext(options_, *entry->command));
  printReport(report, options_);
  return report.exitCode;
}

std::string CommandRegistry::chosenName() const {
  const Entry* entry = chosen();
  return entry == nullptr ? std::string("d2vdb") : entry->command->get_name();
}

std::string CommandRegistry::outOfMemoryAdvice() const {
  const Entry* entry = chosen();
  return entry == nullptr || entry->outOfMemoryAdvice.empty()
             ? std::string("the input is too large for this machine")
             : entry->outOfMemoryAdvice;
}

void printJson(const nlohmann::json& report) {
  // Strings from files (e.g. .vdb metadata) need not be UTF-8: invalid bytes become U+FFFD.
  std::cout << report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << std::endl;
}

namespace {

CLI::Validator numberValidator(bool allowZero) {
  const std::string expected = allowZero ? "a number >= 0" : "a positive number";
  return CLI::Validator(
      [allowZero, expected](std::string& input) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(input, value) || !std::isfinite(value) ||
            (allowZero ? value < 0.0 : !(value > 0.0))) {
          return "must be " + expected + ", got " + input;
        }
        return {};
      },
      allowZero ? "NONNEGATIVE" : "POSITIVE");
}

}  // namespace

void checkResolvesShape(const openvdb::FloatGrid& grid, double longestSide,
                        const std::string& what) {
  const double voxelSize = grid.voxelSize()[0];
  std::ostringstream sizes;
  sizes.precision(6);
  sizes << "voxel size " << voxelSize << " for " << what << " whose longest side is "
        << longestSide;
  if (grid.activeVoxelCount() == 0) {
    throw InputError("the level set is empty (" + sizes.str() +
                     "): nothing was written; use a voxel size well below the longest side, e.g. "
                     "--resolution 64");
  }
  if (voxelSize > longestSide / 4.0) {
    warning("the level set barely resolves " + what + " (" + sizes.str() +
            "); use a smaller voxel size or a larger --resolution");
  }
}

CLI::Validator positiveNumber() {
  return numberValidator(false);
}

CLI::Validator nonNegativeNumber() {
  return numberValidator(true);
}

void declareBudgetOptions(CLI::App& app, ResourceBudget& budget) {
  const auto add = [&app](const std::string& name, std::uint64_t& value, std::uint64_t fallback,
                          const std::string& description) {
    app.add_option_function<std::string>(
           name,
           [&value, name](const std::string& text) {
             try {
               value = parseByteSize(text, name);
             } catch (const InputError& error) {
               throw CLI::ValidationError(error.what());
             }
           },
           description + " (default " + byteSizeText(static_cast<double>(fallback)) +
               "; units k, M, G, T or KiB, MiB, GiB, TiB; 0 = no limit)")
        ->type_name("BYTES");
  };
  add("--max-memory", budget.maxMemoryBytes, kDefaultMaxMemoryBytes,
      "Refuse, before allocating, work whose estimated peak memory exceeds this");
  add("--max-output", budget.maxOutputBytes, kDefaultMaxOutputBytes,
      "Refuse, before writing, outputs whose estimated size (all files together) exceeds this");
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
