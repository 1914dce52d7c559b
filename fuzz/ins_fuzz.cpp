// libFuzzer target for the GNSS/INS readers (io/ins_log.hpp): format detection, the generic CSV
// (io/ins_csv.hpp) under each yaw convention and angle unit, the NovAtel CSV (io/novatel_csv.hpp)
// and KITTI OXTS folders (io/oxts.hpp).
//
// An input holding a line "%%" is an OXTS folder: the text before it is timestamps.txt, each
// following part (up to kMaxOxtsPackets, separated by "%%" lines) one data/NNNNNNNNNN.txt. Any
// other input is one log file, read through detection and then directly by each text reader.
#include <cstddef>
#include <cstdint>

#include "fmt/format.h"
#include "fuzz/fuzz_support.hpp"
#include "x2car/io/ins_csv.hpp"
#include "x2car/io/ins_log.hpp"
#include "x2car/io/novatel_csv.hpp"

namespace {

using namespace x2car;
namespace fs = std::filesystem;

constexpr std::size_t kMaxOxtsPackets = 16;

// Every reader promises finite numbers and strictly increasing times.
void check_records(std::span<const io::InsRecord> records, const char* reader) {
  for (std::size_t i = 0; i < records.size(); ++i) {
    const io::InsRecord& r = records[i];
    fuzz::expect_finite(r.time, reader);
    fuzz::expect_finite_vector(r.position_enu, reader);
    fuzz::expect_finite_vector(r.velocity_enu, reader);
    fuzz::expect_finite(r.attitude.roll, reader);
    fuzz::expect_finite(r.attitude.pitch, reader);
    fuzz::expect_finite(r.attitude.yaw, reader);
    if (i > 0 && !(r.time > records[i - 1].time)) {
      fuzz::finding(std::string(reader) + ": times do not strictly increase");
    }
  }
}

void check_log(const io::InsLog& log) {
  check_records(log.records, "read_ins_log");
  if (log.start_unix_time) fuzz::expect_finite(*log.start_unix_time, "read_ins_log start time");
}

// Rebuilds the scratch OXTS folder from the parts of the input.
fs::path write_oxts_folder(std::span<const std::string_view> parts) {
  const fs::path folder = fuzz::scratch_folder() / "drive" / "oxts";
  std::error_code ignored;
  fs::remove_all(folder, ignored);
  fs::create_directories(folder / "data");
  fuzz::write_scratch_file(folder / "timestamps.txt", parts[0]);
  for (std::size_t i = 1; i < parts.size(); ++i) {
    fuzz::write_scratch_file(folder / "data" / fmt::format("{:010}.txt", i - 1), parts[i]);
  }
  return folder.parent_path();
}

void fuzz_text_log(std::string_view text) {
  const fs::path file = fuzz::scratch_folder() / "ins.csv";
  fuzz::write_scratch_file(file, text);
  fuzz::accept_input_errors("read_ins_log", [&] { check_log(io::read_ins_log(file)); });
  fuzz::accept_input_errors("parse_novatel_enu", [&] {
    check_records(io::parse_novatel_enu(text, "fuzz.csv").records, "parse_novatel_enu");
  });
  for (const io::YawConvention convention :
       {io::YawConvention::kEnu, io::YawConvention::kAzimuth}) {
    io::InsCsvOptions options;
    options.yaw_convention = convention;
    options.angle_unit =
        convention == io::YawConvention::kEnu ? io::AngleUnit::kDegrees : io::AngleUnit::kRadians;
    fuzz::accept_input_errors("parse_ins_csv_log", [&] {
      check_records(io::parse_ins_csv_log(text, "fuzz.csv", options).records, "parse_ins_csv_log");
    });
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = fuzz::as_text(data, size);
  const std::vector<std::string_view> parts = fuzz::split_parts(text, "%%", kMaxOxtsPackets + 1);
  if (parts.size() == 1) {
    fuzz_text_log(text);
    return 0;
  }
  const fs::path drive = write_oxts_folder(parts);
  fuzz::accept_input_errors("read_ins_log (oxts)", [&] { check_log(io::read_ins_log(drive)); });
  return 0;
}
