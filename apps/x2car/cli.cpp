#include "apps/x2car/cli.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/logging.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/core/error.hpp"
#include "x2car_version.hpp"

namespace x2car::cli {
namespace {

constexpr const char* kDescription =
    "x2car finds how each sensor of a car is mounted (the rotation from camera, LiDAR, GNSS/INS "
    "and radar to the car body, and the LiDAR's height above the road) from an ordinary drive.";

constexpr const char* kFooter =
    "Angles follow docs/conventions.md: R_vehicle_from_sensor = Rz(yaw) Ry(pitch) Rx(roll).\n"
    "Exit codes: 0 ok, 1 too little usable data, 2 usage or input error, 3 internal error (a "
    "bug).\n"
    "Run 'x2car SUBCOMMAND --help' for the options of one subcommand.";

int run_chosen(const std::map<CLI::App*, RunCommand>& runners) {
  for (const auto& [command, run] : runners) {
    if (command->parsed()) return run();
  }
  return kExitUsageOrInputError;  // unreachable: a subcommand is required
}

// Every option name of `app` and its subcommands ("--input", "-i").
void collect_option_names(const CLI::App& app, std::set<std::string>& names) {
  for (const CLI::Option* option : app.get_options()) {
    for (const std::string& name : option->get_lnames()) names.insert("--" + name);
    for (const std::string& name : option->get_snames()) names.insert("-" + name);
  }
  for (const CLI::App* subcommand : app.get_subcommands({})) {
    collect_option_names(*subcommand, names);
  }
}

// A file or folder given as "" (`--out=`, an unset shell variable) is a mistake, not "none":
// refuse it at parse time for every option that takes a path.
void refuse_empty_paths(CLI::App& app) {
  const std::set<std::string> kPathTypes{"FILE", "DIR", "PATH", "BAG"};
  for (CLI::Option* option : app.get_options()) {
    if (kPathTypes.count(option->get_type_name()) == 0) continue;
    option->check(CLI::Validator(
        [](const std::string& value) {
          return value.empty() ? std::string("an empty path; give a file or folder name")
                               : std::string();
        },
        "", "non-empty path"));
  }
  for (CLI::App* subcommand : app.get_subcommands({})) refuse_empty_paths(*subcommand);
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substituted = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substituted});
    }
  }
  return row[b.size()];
}

std::string nearest_name_hint(const std::string& name, const std::vector<std::string>& known) {
  const auto nearest = std::min_element(known.begin(), known.end(), [&](auto& a, auto& b) {
    return edit_distance(name, a) < edit_distance(name, b);
  });
  if (nearest == known.end() || edit_distance(name, *nearest) > 2) return {};
  return fmt::format(" (did you mean {}?)", *nearest);
}

// A word where a subcommand is expected that names none ("x2car calibrat", "calibrate camra"):
// CLI11 would only say "A subcommand is required".
std::optional<std::string> unknown_subcommand_message(const CLI::App& app, int argc, char** argv) {
  const CLI::App* current = &app;
  for (int i = 1; i < argc && current->get_require_subcommand_min() > 0; ++i) {
    const std::string word = argv[i];
    if (word.starts_with("-")) continue;  // -v, -q: flags take no value
    std::vector<std::string> names;
    const CLI::App* next = nullptr;
    for (const CLI::App* subcommand : current->get_subcommands({})) {
      names.push_back(subcommand->get_name());
      if (subcommand->get_name() == word) next = subcommand;
    }
    if (next == nullptr) {
      return fmt::format("unknown subcommand '{}' of '{}'{}; choose one of: {}", word,
                         current->get_name(), nearest_name_hint(word, names),
                         fmt::join(names, ", "));
    }
    current = next;
  }
  return std::nullopt;
}

// The first option on the command line that no subcommand knows, with the nearest known name:
// CLI11 reports a missing required option before an unknown one, so "--inptu" would otherwise
// read as "--input is required".
std::optional<std::string> unknown_option_message(const CLI::App& app, int argc, char** argv) {
  std::set<std::string> known;
  collect_option_names(app, known);
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--") break;
    if (argument.size() < 2 || argument[0] != '-') continue;
    if (argument[1] != '-' && std::isdigit(static_cast<unsigned char>(argument[1]))) continue;
    const std::string name = argument.substr(0, argument.find('='));
    // -vv, -qv and the like: each letter a flag.
    if (name[1] != '-' && std::all_of(name.begin() + 1, name.end(), [&](char letter) {
          return known.contains(std::string("-") + letter);
        })) {
      continue;
    }
    if (known.contains(name)) continue;
    return fmt::format("unknown option {}{}; 'x2car SUBCOMMAND --help' lists the options", name,
                       nearest_name_hint(name, {known.begin(), known.end()}));
  }
  return std::nullopt;
}

}  // namespace

int run_cli(int argc, char** argv) {
  CLI::App app{kDescription, "x2car"};
  app.footer(kFooter);
  app.set_version_flag("--version", std::string("x2car ") + kVersion);
  app.require_subcommand(1);
  // Options a subcommand does not know are tried on its parents, so -q and -v work anywhere on
  // the line (subcommands inherit this setting).
  app.fallthrough();
  int verbose = 0;
  bool quiet = false;
  app.add_flag("-v,--verbose", verbose, "More detail on stderr (-vv for tracing)");
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors on stderr");

  std::map<CLI::App*, RunCommand> runners;
  for (const Subcommand& subcommand : subcommand_table()) {
    CLI::App* command = app.add_subcommand(subcommand.name, subcommand.summary);
    runners[command] = subcommand.setup(*command);
  }
  refuse_empty_paths(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() != 0) {
      auto message = unknown_subcommand_message(app, argc, argv);
      if (!message) message = unknown_option_message(app, argc, argv);
      if (message) {
        std::cerr << "error: " << *message << "\n";
        return kExitUsageOrInputError;
      }
    }
    const int code = app.exit(error);  // prints help, the version, or the usage error
    return code == 0 ? kExitOk : kExitUsageOrInputError;
  }
  configure_logging(quiet ? -1 : verbose);

  try {
    return run_chosen(runners);
  } catch (const InputError& error) {
    spdlog::error("{}", error.what());
    return kExitUsageOrInputError;
  } catch (const std::invalid_argument& error) {  // an option out of range (Options::Check)
    spdlog::error("{}", error.what());
    return kExitUsageOrInputError;
  } catch (const std::bad_alloc&) {
    spdlog::error(
        "internal error: out of memory. No input should need this much; please report it with "
        "the command line and the input (a bug in x2car)");
  } catch (const std::exception& error) {
    spdlog::error(
        "internal error: {}. This is a bug in x2car; please report it with the "
        "command line and the input",
        error.what());
  }
  return kExitInternalError;
}

}  // namespace x2car::cli
