#include <array>

#include "apps/x2car/subcommand.hpp"

namespace x2car::cli {

std::span<const Subcommand> subcommand_table() {
  static constexpr std::array kSubcommands = {
      Subcommand{
          "convert",
          "Convert an extrinsic between xyz+rpy, 4x4 matrix, quaternion, URDF, Autoware YAML "
          "and the reference tool's text",
          &setup_convert_command},
      Subcommand{"simulate",
                 "Simulate a drive: sensor data and ground truth, the test bench of every "
                 "accuracy claim",
                 &setup_simulate_command},
      Subcommand{"calibrate",
                 "Find a sensor's mounting (rotation to the car body) from a drive: calibrate "
                 "ins|lidar|radar|camera|all",
                 &setup_calibrate_command},
      Subcommand{"eval",
                 "The paper's protocol: calibrate a drive folder's sensors on every minute, the "
                 "spread of the estimates and their errors against the truth",
                 &setup_eval_command},
      Subcommand{"report",
                 "One HTML file a person can check: results, their evidence as charts, the "
                 "segments of an evaluation, a camera's frames and a view to adjust them",
                 &setup_report_command},
      Subcommand{"inspect",
                 "What a bag holds (MCAP, ROS 1, ROS 2): its topics, types, counts, rates, and "
                 "which calibrator reads each",
                 &setup_inspect_command},
      Subcommand{"camera-net",
                 "The paper's learned vanishing-point and horizon network: train it on simulated "
                 "drives, score it (calibrate camera --estimator learned uses it)",
                 &setup_camera_net_command},
  };
  return kSubcommands;
}

}  // namespace x2car::cli
