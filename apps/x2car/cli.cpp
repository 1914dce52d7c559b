#include "apps/x2car/cli.hpp"

#include <spdlog/spdlog.h>

#include <map>

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
    "Exit codes: 0 ok, 1 too little usable data, 2 usage or input error.\n"
    "Run 'x2car SUBCOMMAND --help' for the options of one subcommand.";

int run_chosen(const std::map<CLI::App*, RunCommand>& runners) {
  for (const auto& [command, run] : runners) {
    if (command->parsed()) return run();
  }
  return kExitUsageOrInputError;  // unreachable: a subcommand is required
}

}  // namespace

int run_cli(int argc, char** argv) {
  CLI::App app{kDescription, "x2car"};
  app.footer(kFooter);
  app.set_version_flag("--version", std::string("x2car ") + kVersion);
  app.require_subcommand(1);
  int verbose = 0;
  bool quiet = false;
  app.add_flag("-v,--verbose", verbose, "More detail on stderr (-vv for tracing)");
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors on stderr");

  std::map<CLI::App*, RunCommand> runners;
  for (const Subcommand& subcommand : subcommand_table()) {
    CLI::App* command = app.add_subcommand(subcommand.name, subcommand.summary);
    runners[command] = subcommand.setup(*command);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);  // prints help, the version, or the usage error
    return code == 0 ? kExitOk : kExitUsageOrInputError;
  }
  configure_logging(quiet ? -1 : verbose);

  try {
    return run_chosen(runners);
  } catch (const InputError& error) {
    spdlog::error("{}", error.what());
  } catch (const std::invalid_argument& error) {
    spdlog::error("{}", error.what());
  } catch (const std::exception& error) {
    spdlog::error("unexpected failure: {}", error.what());
  }
  return kExitUsageOrInputError;
}

}  // namespace x2car::cli
