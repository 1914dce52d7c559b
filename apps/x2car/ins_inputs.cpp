#include "apps/x2car/ins_inputs.hpp"

#include <spdlog/spdlog.h>

#include <system_error>

#include "x2car/core/error.hpp"
#include "x2car/io/drive_folder.hpp"

namespace x2car::cli {

std::filesystem::path ins_log_of(const std::filesystem::path& input) {
  std::error_code error;
  if (!std::filesystem::is_directory(input, error)) return input;
  const bool drive = std::filesystem::exists(input / "ins", error) ||
                     std::filesystem::exists(input / io::kDriveManifestName, error);
  if (!drive) return input;
  const io::DriveFolder folder = io::find_drive_sensors(input);
  if (!folder.ins_log) {
    throw InputError(input.string(),
                     "the drive folder has no GNSS/INS log (ins/novatel_enu.csv, "
                     "or a sensor of type ins in x2car.yaml)");
  }
  const std::filesystem::path log = folder.ins_log->lexically_normal();
  spdlog::info("the drive's GNSS/INS log: {}", log.string());
  return log;
}

}  // namespace x2car::cli
