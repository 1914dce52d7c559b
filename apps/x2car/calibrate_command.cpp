// x2car calibrate SENSOR: one subcommand per calibrator, each in its own file
// (calibrate_ins_command.cpp, ...), sharing the output options of calibration_output.hpp.
#include <array>
#include <map>

#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/subcommand.hpp"

namespace x2car::cli {
namespace {

constexpr std::array kCalibrators = {
    Subcommand{"ins",
               "GNSS/INS -> car: yaw (track heading or velocity direction) and pitch "
               "(non-holonomic), from a novatel_enu.csv, generic CSV or KITTI OXTS log",
               &setup_calibrate_ins_command},
    Subcommand{"lidar",
               "LiDAR -> car: roll, pitch and height (ground plane) and yaw (odometry track), "
               "from a folder of PCD or KITTI sweeps",
               &setup_calibrate_lidar_command},
    Subcommand{"radar",
               "radar -> car: yaw by the velocity method (Doppler of static targets) and the "
               "position method (static tracks), auto choosing, from Conti, Delphi or generic "
               "radar files and a GNSS/INS log",
               &setup_calibrate_radar_command},
    Subcommand{"camera",
               "camera -> car: roll, pitch and yaw from the road's vanishing point and the "
               "horizon in steady stretches, from a folder of images or a video and the "
               "intrinsics",
               &setup_calibrate_camera_command},
    Subcommand{"all",
               "every sensor of a drive folder (ins/, lidar*/, radar*/, camera*/), each by its "
               "own command; one JSON, YAML and URDF for all, and a table against the truth",
               &setup_calibrate_all_command},
};

}  // namespace

RunCommand setup_calibrate_command(CLI::App& command) {
  command.require_subcommand(1);
  auto runners = std::make_shared<std::map<CLI::App*, RunCommand>>();
  for (const Subcommand& calibrator : kCalibrators) {
    CLI::App* sub = command.add_subcommand(calibrator.name, calibrator.summary);
    (*runners)[sub] = calibrator.setup(*sub);
  }
  command.footer(
      "Exit codes: 0 a result, 1 too little usable data (the reason is printed), 2 usage or input "
      "error, 3 internal error (a bug).\nRun 'x2car calibrate SENSOR --help' for one sensor's "
      "options.");
  return [runners] {
    for (const auto& [sub, run] : *runners) {
      if (sub->parsed()) return run();
    }
    return static_cast<int>(kExitUsageOrInputError);  // unreachable: a sensor is required
  };
}

}  // namespace x2car::cli
