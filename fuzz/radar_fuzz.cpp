// libFuzzer target for the radar readers (io/radar_csv.hpp): one Conti scan file
// (io/radar_conti.hpp), one Delphi scan file (io/radar_delphi.hpp) and the generic CSV. Every
// input goes to all three; the scan rows then go through make_radar_log and split_radar_scans as
// a folder's would.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_support.hpp"
#include "x2car/io/radar_conti.hpp"
#include "x2car/io/radar_csv.hpp"
#include "x2car/io/radar_delphi.hpp"

namespace {

using namespace x2car;

// The readers promise finite numbers (rcs may be absent) and detections in time order.
void check_log(const io::RadarLog& log, const char* reader) {
  fuzz::expect_finite(log.start_unix_time, reader);
  for (std::size_t i = 0; i < log.detections.size(); ++i) {
    const io::RadarDetection& d = log.detections[i];
    for (const double value : {d.time, d.range, d.azimuth, d.range_rate, d.x, d.y, d.vx, d.vy}) {
      fuzz::expect_finite(value, reader);
    }
    if (d.rcs_dbsm) fuzz::expect_finite(*d.rcs_dbsm, reader);
    if (i > 0 && d.time < log.detections[i - 1].time) {
      fuzz::finding(std::string(reader) + ": detections out of time order");
    }
  }
  io::split_radar_scans(log.detections);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = fuzz::as_text(data, size);
  fuzz::accept_input_errors("parse_conti_scan", [&] {
    check_log(io::make_radar_log(io::parse_conti_scan(text, "fuzz.csv")), "parse_conti_scan");
  });
  fuzz::accept_input_errors("parse_delphi_scan", [&] {
    check_log(io::make_radar_log(io::parse_delphi_scan(text, "fuzz.csv")), "parse_delphi_scan");
  });
  fuzz::accept_input_errors("parse_radar_csv", [&] {
    check_log(io::parse_radar_csv(text, "fuzz.csv"), "parse_radar_csv");
  });
  io::parse_radar_scan_file_name(text.substr(0, 64));
  return 0;
}
