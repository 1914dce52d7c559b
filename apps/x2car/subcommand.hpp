// The subcommand table: each subcommand lives in its own file and registers itself here by one
// entry. Only working subcommands are listed.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <span>

namespace x2car::cli {

// Runs the subcommand after parsing and returns its exit code (exit_codes.hpp).
using RunCommand = std::function<int()>;

struct Subcommand {
  const char* name;
  const char* summary;  // one line for `x2car --help`
  // Adds the subcommand's options to `command` and returns the function that runs it with them.
  RunCommand (*setup)(CLI::App& command);
};

std::span<const Subcommand> subcommand_table();

// One entry per file: convert_command.cpp, simulate_command.cpp, ...
RunCommand setup_convert_command(CLI::App& command);
RunCommand setup_simulate_command(CLI::App& command);
RunCommand setup_calibrate_command(CLI::App& command);
RunCommand setup_eval_command(CLI::App& command);
RunCommand setup_report_command(CLI::App& command);
RunCommand setup_inspect_command(CLI::App& command);
RunCommand setup_camera_net_command(CLI::App& command);

// The calibrators under `x2car calibrate`: calibrate_ins_command.cpp, ...
RunCommand setup_calibrate_all_command(CLI::App& command);
RunCommand setup_calibrate_camera_command(CLI::App& command);
RunCommand setup_calibrate_ins_command(CLI::App& command);
RunCommand setup_calibrate_lidar_command(CLI::App& command);
RunCommand setup_calibrate_radar_command(CLI::App& command);

}  // namespace x2car::cli
