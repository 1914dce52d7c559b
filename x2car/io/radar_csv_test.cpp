// Tests of the three radar layouts: Conti and Delphi scan folders and the generic CSV.
#include "x2car/io/radar_csv.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/radar_conti.hpp"
#include "x2car/io/radar_delphi.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;
using x2car::testing::expect_input_error;

constexpr std::int64_t kNs = 1000000000;
constexpr double kStart = 1780308000.0;  // 2026-06-01 10:00:00 UTC

std::filesystem::path temp_folder(const std::string& name) {
  const auto path = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path;
}

// Three scans 72 ms apart with ids out of order, new and continuing tracks, awkward numbers.
std::vector<RadarDetection> sample_detections() {
  std::vector<RadarDetection> detections;
  const std::vector<std::vector<int>> ids{{7, 0, 63}, {0, 12}, {63, 5, 1, 40}};
  for (std::size_t scan = 0; scan < ids.size(); ++scan) {
    for (std::size_t k = 0; k < ids[scan].size(); ++k) {
      const double s = static_cast<double>(scan * 10 + k);
      RadarDetection d;
      d.time = 0.072 * static_cast<double>(scan);
      d.track_id = ids[scan][k];
      d.new_track = (scan + k) % 2 == 0;
      d.x = 10.0 / 3.0 + s;
      d.y = -2.0 + 0.37 * s;
      d.has_velocity = true;
      d.vx = -8.123456789 + 0.1 * s;
      d.vy = 1e-3 * s - 0.5;
      d.rcs_dbsm = 5.25 - s;
      set_polar_from_cartesian(d);
      d.range_rate += 0.01 * s;  // a measured range rate need not equal the velocity's
      detections.push_back(d);
    }
  }
  return detections;
}

void write(const std::filesystem::path& path, const std::string& text) {
  write_text_file(path, text);
}

// ---- scan file names and UTC -------------------------------------------------------------------

TEST(RadarScanFileName, NamesTheFirstRowsUtcMillisecond) {
  EXPECT_EQ(radar_scan_file_name(1780308000 * kNs), "2026-06-01-10-00-00-000.csv");
  EXPECT_EQ(radar_scan_file_name(1780308000 * kNs + 72999999), "2026-06-01-10-00-00-072.csv");
  EXPECT_EQ(radar_scan_file_name(1709251199 * kNs + 999999999), "2024-02-29-23-59-59-999.csv");
  EXPECT_EQ(radar_scan_file_name(-1), "1969-12-31-23-59-59-999.csv");
  EXPECT_EQ(parse_radar_scan_file_name("2026-06-01-10-00-00-072.csv"), 1780308000 * kNs + 72000000);
  EXPECT_EQ(parse_radar_scan_file_name("2024-02-29-23-59-59-999.csv"),
            1709251199 * kNs + 999000000);
}

TEST(RadarScanFileName, RejectsOtherNames) {
  for (const char* name :
       {"2026-06-01 10-00-00-072.csv", "2026-06-01-10-00-00.csv", "2026-06-01-10-00-00-72.csv",
        "2026-13-01-10-00-00-072.csv", "2026-02-29-10-00-00-072.csv", "2026-06-01-10-00-00-072",
        "2026-06-01-10:00:00-072.csv", "2026-06-01-10-00-00-0720.csv", "scan.csv", ""}) {
    EXPECT_FALSE(parse_radar_scan_file_name(name).has_value()) << name;
  }
}

TEST(RadarScanFileName, DoesNotDependOnTheMachinesTimeZone) {
  const char* old = std::getenv("TZ");
  const std::string saved = old ? old : "";
  for (const char* zone : {"America/New_York", "Asia/Kolkata", "UTC"}) {
    setenv("TZ", zone, 1);
    tzset();
    EXPECT_EQ(radar_scan_file_name(1780308000 * kNs + 5000000), "2026-06-01-10-00-00-005.csv")
        << zone;
    EXPECT_EQ(parse_radar_scan_file_name("2026-06-01-10-00-00-005.csv"),
              1780308000 * kNs + 5000000);
  }
  if (old) {
    setenv("TZ", saved.c_str(), 1);
  } else {
    unsetenv("TZ");
  }
  tzset();
}

// ---- round trips
// ---------------------------------------------------------------------------------

// Rows come back sorted by time and, within a scan, by track id.
std::vector<RadarDetection> sorted_like_a_scan_folder(std::vector<RadarDetection> detections) {
  std::stable_sort(detections.begin(), detections.end(), [](const auto& a, const auto& b) {
    return a.time != b.time ? a.time < b.time : a.track_id < b.track_id;
  });
  return detections;
}

TEST(ContiRadar, RoundTripsOneFilePerScanInAscendingTrackId) {
  const auto folder = temp_folder("conti_round_trip");
  const std::vector<RadarDetection> written = sample_detections();
  write_conti_radar(folder, written, kStart);
  const auto files = list_radar_scan_files(folder);
  ASSERT_EQ(files.size(), 3u);
  EXPECT_EQ(files[1].path.filename().string(), "2026-06-01-10-00-00-072.csv");
  const std::string first = read_text_file(files[0].path);
  EXPECT_THAT(first, ::testing::StartsWith(std::string(kContiHeader) + "\n1780308000000000000,0,"));

  const RadarLog log = read_conti_radar(folder);
  EXPECT_EQ(log.start_unix_time, kStart);
  const std::vector<RadarDetection> expected = sorted_like_a_scan_folder(written);
  ASSERT_EQ(log.detections.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const RadarDetection& a = log.detections[i];
    const RadarDetection& e = expected[i];
    EXPECT_NEAR(a.time, e.time, 1e-9);
    EXPECT_EQ(a.track_id, e.track_id);
    EXPECT_EQ(a.new_track, e.new_track);
    EXPECT_EQ(a.x, e.x);
    EXPECT_EQ(a.y, e.y);
    EXPECT_EQ(a.vx, e.vx);
    EXPECT_EQ(a.vy, e.vy);
    EXPECT_EQ(a.rcs_dbsm, e.rcs_dbsm);
    EXPECT_TRUE(a.has_velocity);
    EXPECT_DOUBLE_EQ(a.range, e.range);
    EXPECT_DOUBLE_EQ(a.azimuth, e.azimuth);
    // Conti has no range-rate column: it is the velocity along the line of sight.
    EXPECT_NEAR(a.range_rate, (e.x * e.vx + e.y * e.vy) / e.range, 1e-12);
  }
}

TEST(DelphiRadar, RoundTrips15FieldsAndSkipsNoTrackRows) {
  const auto folder = temp_folder("delphi_round_trip");
  const std::vector<RadarDetection> written = sample_detections();
  write_delphi_radar(folder, written, kStart);
  const auto files = list_radar_scan_files(folder);
  ASSERT_EQ(files.size(), 3u);
  const std::string third_scan = read_text_file(files[2].path);
  const std::vector<std::string_view> row = split_fields(split_lines(third_scan).front().text);
  ASSERT_EQ(row.size(), 15u);
  EXPECT_EQ(row[0], "1780308000144000000");
  EXPECT_EQ(row[1], "1");   // ascending track id
  EXPECT_EQ(row[13], "2");  // scan index

  const RadarLog log = read_delphi_radar(folder);
  EXPECT_EQ(log.start_unix_time, kStart);
  const std::vector<RadarDetection> expected = sorted_like_a_scan_folder(written);
  ASSERT_EQ(log.detections.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const RadarDetection& a = log.detections[i];
    const RadarDetection& e = expected[i];
    EXPECT_NEAR(a.time, e.time, 1e-9);
    EXPECT_EQ(a.track_id, e.track_id);
    EXPECT_EQ(a.new_track, e.new_track);
    EXPECT_EQ(a.range, e.range);
    EXPECT_EQ(a.azimuth, e.azimuth);
    EXPECT_EQ(a.range_rate, e.range_rate);
    EXPECT_EQ(a.vx, e.vx);
    EXPECT_EQ(a.vy, e.vy);
    EXPECT_NEAR(a.x, e.x, 1e-12);
    EXPECT_NEAR(a.y, e.y, 1e-12);
    EXPECT_EQ(a.rcs_dbsm, e.rcs_dbsm);
  }

  // Status 0 and 6 rows are empty track slots; a header line is tolerated.
  const auto slots = temp_folder("delphi_slots");
  write(slots / "2026-06-01-10-00-00-000.csv",
        "time_ns,id,x,y,vx,vy,status,bearing,range,rcs,acc,lat,width,scan,range_rate\n"
        "1780308000000000000,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n"
        "1780308000000000000,1,10,0,-5,0,1,0,10,3,0,0,0,0,-5\n"
        "1780308000000000000,2,0,0,0,0,6,0,0,0,0,0,0,0,0\n"
        "1780308000000000000,3,0,10,-5,0,4,1.5707963267948966,10,3,0,0,0,0,0\n");
  const RadarLog with_slots = read_delphi_radar(slots);
  ASSERT_EQ(with_slots.detections.size(), 2u);
  EXPECT_EQ(with_slots.detections[0].track_id, 1);
  EXPECT_TRUE(with_slots.detections[0].new_track);
  EXPECT_EQ(with_slots.detections[1].track_id, 3);
  EXPECT_FALSE(with_slots.detections[1].new_track);
  EXPECT_NEAR(with_slots.detections[1].y, 10.0, 1e-12);
}

TEST(GenericRadarCsv, RoundTripsEveryColumnAndEmptyOptionalFields) {
  std::vector<RadarDetection> written = sample_detections();
  written[1].track_id = kNoTrackId;
  written[2].has_velocity = false;
  written[2].vx = written[2].vy = 0.0;
  written[3].rcs_dbsm.reset();
  const RadarLog log = parse_radar_csv(format_radar_csv(written), "radar.csv");
  EXPECT_EQ(log.start_unix_time, 0.0);
  ASSERT_EQ(log.detections.size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    const RadarDetection& a = log.detections[i];
    const RadarDetection& e = written[i];
    EXPECT_EQ(a.time, e.time);
    EXPECT_EQ(a.track_id, e.track_id);
    EXPECT_EQ(a.range, e.range);
    EXPECT_EQ(a.azimuth, e.azimuth);
    EXPECT_EQ(a.range_rate, e.range_rate);
    EXPECT_EQ(a.x, e.x);
    EXPECT_EQ(a.y, e.y);
    EXPECT_EQ(a.has_velocity, e.has_velocity);
    EXPECT_EQ(a.vx, e.vx);
    EXPECT_EQ(a.vy, e.vy);
    EXPECT_EQ(a.rcs_dbsm, e.rcs_dbsm);
  }
}

TEST(GenericRadarCsv, ReadsTheRequiredColumnsInAnyOrder) {
  const RadarLog log = parse_radar_csv(
      "range_rate,azimuth,range,time,comment\n-3,0.5,20,0.1,x\n1,-0.25,4,0.05,y\n", "r.csv");
  ASSERT_EQ(log.detections.size(), 2u);
  const RadarDetection& first = log.detections[0];  // sorted by time
  EXPECT_EQ(first.time, 0.05);
  EXPECT_EQ(first.track_id, kNoTrackId);
  EXPECT_FALSE(first.has_velocity);
  EXPECT_FALSE(first.rcs_dbsm.has_value());
  EXPECT_NEAR(first.x, 4.0 * std::cos(-0.25), 1e-12);
  EXPECT_NEAR(first.y, 4.0 * std::sin(-0.25), 1e-12);
  EXPECT_EQ(log.detections[1].range_rate, -3.0);
}

TEST(RadarLayouts, WriteAndReadByName) {
  for (const char* name : {"conti", "delphi", "generic"}) {
    const RadarLayout layout = radar_layout_from_string(name);
    EXPECT_EQ(to_string(layout), name);
    const auto folder = temp_folder(std::string("layout_") + name);
    write_radar(folder / "radar", layout, sample_detections(), kStart);
    const RadarLog log = read_radar(folder / "radar", layout);
    EXPECT_EQ(log.detections.size(), sample_detections().size()) << name;
  }
  EXPECT_THROW(radar_layout_from_string("bosch"), std::invalid_argument);
}

TEST(RadarWriters, RejectWhatTheLayoutCannotHold) {
  const auto folder = temp_folder("radar_writer_errors");
  std::vector<RadarDetection> detections = sample_detections();
  detections[0].track_id = 100;
  EXPECT_THROW(write_conti_radar(folder, detections, kStart), std::invalid_argument);
  detections[0].track_id = 64;
  EXPECT_THROW(write_delphi_radar(folder, detections, kStart), std::invalid_argument);
  detections = sample_detections();
  detections[1].track_id = detections[0].track_id;
  EXPECT_THROW(write_conti_radar(folder, detections, kStart), std::invalid_argument);
  detections = sample_detections();
  detections[0].has_velocity = false;
  EXPECT_THROW(write_delphi_radar(folder, detections, kStart), std::invalid_argument);
  detections = sample_detections();
  for (auto& d : detections) d.time = d.time > 0.1 ? 0.0725 : d.time;  // 0.5 ms after a scan
  EXPECT_THROW(write_conti_radar(folder, detections, kStart), std::invalid_argument);
}

// ---- errors
// --------------------------------------------------------------------------------------

// Writes `text` as a Conti scan file and reads the folder, expecting an InputError there.
void expect_conti_error(const std::string& text, std::size_t line, const std::string& field) {
  const auto folder = temp_folder("conti_error");
  const auto file = folder / "2026-06-01-10-00-00-000.csv";
  write(file, text);
  expect_input_error([&] { read_conti_radar(folder); }, file.string(), line, field);
}

void expect_delphi_error(const std::string& text, std::size_t line, const std::string& field) {
  const auto folder = temp_folder("delphi_error");
  const auto file = folder / "2026-06-01-10-00-00-000.csv";
  write(file, text);
  expect_input_error([&] { read_delphi_radar(folder); }, file.string(), line, field);
}

constexpr char kContiHead[] = "time_ns,track_id,vx,vy,px,py,rcs,meas_state\n";

TEST(ContiRadar, RejectsBadRowsNamingFileLineAndField) {
  const std::string head = kContiHead;
  expect_conti_error(head + "1780308000000000000,3,1,2,3,4,5\n", 2, "");
  expect_conti_error(head + "1780308000000000000,3,1,2,3,4,5,1,9\n", 2, "");
  expect_conti_error(head + "1780308000000000000,3,fast,2,3,4,5,1\n", 2, "vx");
  expect_conti_error(head + "1780308000000000000,100,1,2,3,4,5,1\n", 2, "track_id");
  expect_conti_error(head + "1780308000000000000,-1,1,2,3,4,5,1\n", 2, "track_id");
  expect_conti_error(head + "1780308000000000000,2.5,1,2,3,4,5,1\n", 2, "track_id");
  expect_conti_error(head + "1780308000.5,2,1,2,3,4,5,1\n", 2, "time_ns");
  expect_conti_error(head + "1780308000000000000,4,1,2,3,nan,5,1\n", 2, "py");
  expect_conti_error(
      head + "1780308000000000000,4,1,2,3,4,5,1\n1780308000000000000,4,1,2,3,4,5,2\n", 3,
      "track_id");
  expect_conti_error("time_ns,id,vx,vy,px,py\n", 1, "2");
  const InputError error = [&] {
    const auto folder = temp_folder("conti_bad_id_message");
    write(folder / "2026-06-01-10-00-00-000.csv", head + "1780308000000000000,100,1,2,3,4,5,1\n");
    return x2car::testing::input_error_of([&] { read_conti_radar(folder); });
  }();
  EXPECT_THAT(error.what(), HasSubstr("outside 0-99"));
}

TEST(DelphiRadar, RejectsBadRowsNamingFileLineAndField) {
  const std::string row = "1780308000000000000,5,10,0,-5,0,3,0,10,3,0,0,0,0,-5";
  expect_delphi_error(row + ",0\n", 1, "");
  expect_delphi_error("1780308000000000000,5,10,0,-5,0,3,0,10,3,0,0,0,-5\n", 1, "");
  expect_delphi_error(row + "\n" + "1780308000000000000,64,10,0,-5,0,3,0,10,3,0,0,0,0,-5\n", 2,
                      "track_id");
  expect_delphi_error("1780308000000000000,5,10,0,-5,0,3,left,10,3,0,0,0,0,-5\n", 1, "bearing");
  expect_delphi_error("1780308000000000000,5,10,0,-5,0,3,0,-10,3,0,0,0,0,-5\n", 1, "range");
  expect_delphi_error("1780308000000000000,5,10,0,-5,0,3.5,0,10,3,0,0,0,0,-5\n", 1, "status");
  expect_delphi_error("1780308000000000000,5,10,0,-5,0,3,0,10,3,0,0,0,0,\n", 1, "range_rate");
}

TEST(GenericRadarCsv, RejectsBadInputNamingLineAndField) {
  const auto expect_error = [](const std::string& text, std::size_t line,
                               const std::string& field) {
    expect_input_error([&] { parse_radar_csv(text, "radar.csv"); }, "radar.csv", line, field);
  };
  expect_error("time,range,azimuth\n0,1,2\n", 1, "range_rate");
  expect_error("time,range,azimuth,range_rate,range\n0,1,2,3,4\n", 1, "range");
  expect_error("time,range,azimuth,range_rate,vx\n0,1,2,3,4\n", 1, "vy");
  expect_error("time,range,azimuth,range_rate\n0,1,2\n", 2, "");
  expect_error("time,range,azimuth,range_rate\n0,1,2,3\n0,1,2,3,4\n", 3, "");
  expect_error("time,range,azimuth,range_rate\n0,one,2,3\n", 2, "range");
  expect_error("time,track_id,range,azimuth,range_rate\n0,-3,1,2,3\n", 2, "track_id");
  expect_error("time,track_id,range,azimuth,range_rate\n0,1.5,1,2,3\n", 2, "track_id");
  expect_error("time,range,azimuth,range_rate,vx,vy\n0,1,2,3,4,\n", 2, "vy");
  expect_input_error([] { parse_radar_csv("time,range,azimuth,range_rate\n", "radar.csv"); },
                     "radar.csv", 0);
}

// ---- issue 11: layouts told apart, plausibility, notices ---------------------------------------

TEST(RadarLayouts, AutoDetectsEachLayoutFromTheFiles) {
  for (const RadarLayout layout :
       {RadarLayout::kConti, RadarLayout::kDelphi, RadarLayout::kGeneric}) {
    const auto folder = temp_folder("detect_" + to_string(layout));
    write_radar(folder / "radar", layout, sample_detections(), kStart);
    EXPECT_EQ(detect_radar_layout(folder / "radar"), layout) << to_string(layout);
    const RadarLog log = read_radar(folder / "radar", RadarReadOptions{});
    EXPECT_EQ(log.layout, layout);
    EXPECT_EQ(log.detections.size(), sample_detections().size()) << to_string(layout);
  }
  const auto file = temp_folder("detect_file") / "any.csv";
  write(file, "time,range,azimuth,range_rate\n0,1,0,0\n");
  EXPECT_EQ(detect_radar_layout(file), RadarLayout::kGeneric);
  const auto unknown = temp_folder("detect_unknown");
  write(unknown / "2026-06-01-10-00-00-000.csv", "1,2,3\n");
  const InputError error = expect_input_error(
      [&] { detect_radar_layout(unknown); }, (unknown / "2026-06-01-10-00-00-000.csv").string(), 1);
  EXPECT_THAT(error.what(), HasSubstr("--layout"));
  expect_input_error([&] { detect_radar_layout(unknown / "missing"); },
                     (unknown / "missing").string(), 0);
}

// Generic files read as conti used to say only "not a folder" / a header error, not that the
// layout is wrong.
TEST(RadarLayouts, AWrongLayoutErrorNamesTheLayoutTheFilesLookLike) {
  const auto folder = temp_folder("wrong_layout");
  write_radar(folder / "delphi", RadarLayout::kDelphi, sample_detections(), kStart);
  write_radar(folder / "generic", RadarLayout::kGeneric, sample_detections(), kStart);
  const InputError as_conti =
      x2car::testing::input_error_of([&] { read_radar(folder / "delphi", RadarLayout::kConti); });
  EXPECT_THAT(as_conti.what(), HasSubstr("look like the delphi layout: pass --layout delphi"));
  EXPECT_THAT(as_conti.what(), HasSubstr("column 1 is '1780308000000000000'"));
  const InputError as_delphi =
      x2car::testing::input_error_of([&] { read_radar(folder / "generic", RadarLayout::kDelphi); });
  EXPECT_THAT(as_delphi.what(), HasSubstr("pass --layout generic"));
  const InputError as_generic =
      x2car::testing::input_error_of([&] { read_radar(folder / "delphi", RadarLayout::kGeneric); });
  EXPECT_THAT(as_generic.what(), HasSubstr("pass --layout delphi"));
}

// The Conti header error named the expected column as if it were the one found.
TEST(ContiRadar, HeaderErrorNamesTheColumnFoundAndTheOneExpected) {
  const auto folder = temp_folder("conti_header");
  const auto file = folder / "2026-06-01-10-00-00-000.csv";
  write(file, "time_ns,id,vx,vy,px,py\n");
  const InputError error =
      expect_input_error([&] { read_conti_radar(folder); }, file.string(), 1, "2");
  EXPECT_THAT(error.what(), HasSubstr("column 2 is 'id', expected 'track_id'"));
  write(file, "time_ns,track_id,vx\n");
  const InputError short_header =
      expect_input_error([&] { read_conti_radar(folder); }, file.string(), 1, "4");
  EXPECT_THAT(short_header.what(), HasSubstr("column 4 is missing, expected 'vy'"));
}

TEST(RadarNotices, IgnoredColumnsAreNamed) {
  const RadarLog generic =
      parse_radar_csv("time,range,azimuth,range_rate,snr\n0,1,0,0,7\n", "radar.csv");
  ASSERT_EQ(generic.notices.size(), 1u);
  EXPECT_THAT(generic.notices[0], HasSubstr("radar.csv:1: ignored column(s) 'snr' (5)"));
  const auto folder = temp_folder("conti_extra_column");
  write(folder / "2026-06-01-10-00-00-000.csv",
        "time_ns,track_id,vx,vy,px,py,rcs,meas_state,prob\n"
        "1780308000000000000,3,1,2,3,4,5,1,0.9\n");
  const RadarLog conti = read_conti_radar(folder);
  ASSERT_EQ(conti.notices.size(), 1u);
  EXPECT_THAT(conti.notices[0], HasSubstr("'prob' (9)"));
}

TEST(GenericRadarCsv, SemicolonSeparatedFilesAreRead) {
  const RadarLog log = parse_radar_csv("time;range;azimuth;range_rate\n0;10;0.5;-3\n", "r.csv");
  ASSERT_EQ(log.detections.size(), 1u);
  EXPECT_EQ(log.detections[0].range, 10.0);
  EXPECT_EQ(log.detections[0].azimuth, 0.5);
}

TEST(RadarPlausibility, NegativeRangesAndAzimuthsBeyondPiAreErrorsWithAHint) {
  const std::string head = "time,range,azimuth,range_rate\n";
  expect_input_error([&] { parse_radar_csv(head + "0,-1,0,0\n", "r.csv"); }, "r.csv", 2, "range");
  const InputError degrees = expect_input_error(
      [&] { parse_radar_csv(head + "0,10,0.5,0\n0,10,45,0\n", "r.csv"); }, "r.csv", 3, "azimuth");
  EXPECT_THAT(degrees.what(), HasSubstr("--angle-unit deg"));
  const RadarLog log = parse_radar_csv(head + "0,10,45,0\n", "r.csv", AngleUnit::kDegrees);
  EXPECT_DOUBLE_EQ(log.detections[0].azimuth, rad_from_deg(45.0));
  EXPECT_NEAR(log.detections[0].x, 10.0 * std::cos(rad_from_deg(45.0)), 1e-12);
  expect_input_error([&] { parse_radar_csv(head + "0,10,270,0\n", "r.csv", AngleUnit::kDegrees); },
                     "r.csv", 2, "azimuth");
  expect_delphi_error("1780308000000000000,5,10,0,-5,0,3,30,10,3,0,0,0,0,-5\n", 1, "bearing");
  expect_delphi_error("1780308000000000000,5,10,0,-5,0,3,0,1e5,3,0,0,0,0,-5\n", 1, "range");
  expect_conti_error(std::string(kContiHead) + "1780308000000000000,3,1,2,1e308,4,5,1\n", 2, "px");
  expect_conti_error(std::string(kContiHead) + "1780308000000000000,3,-2e3,2,3,4,5,1\n", 2, "vx");
  expect_input_error([&] { parse_radar_csv(head + "0,10,0.5,-1e300\n", "r.csv"); }, "r.csv", 2,
                     "range_rate");
  const std::vector<StampedRadarDetection> rows = parse_delphi_scan(
      "1780308000000000000,5,10,0,-5,0,3,30,10,3,0,0,0,0,-5\n", "d.csv", AngleUnit::kDegrees);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_DOUBLE_EQ(rows[0].detection.azimuth, rad_from_deg(30.0));
}

TEST(GenericRadarCsv, MixedClocksAreRejected) {
  const InputError error = expect_input_error(
      [&] {
        parse_radar_csv("time,range,azimuth,range_rate\n1.5,1,0,0\n1780308000.5,1,0,0\n", "r.csv");
      },
      "r.csv", 3, "time");
  EXPECT_THAT(error.what(), HasSubstr("mixed clocks"));
}

TEST(RadarScanFolders, RejectMissingFoldersAndFileNamesThatAreNotTimes) {
  const auto folder = temp_folder("radar_bad_names");
  expect_input_error([&] { read_conti_radar(folder / "missing"); }, (folder / "missing").string(),
                     0);
  expect_input_error([&] { read_delphi_radar(folder); }, folder.string(), 0);  // no .csv files
  write(folder / "notes.txt", "ignored\n");
  write(folder / "2026-06-01-10-00-00-000.csv", std::string(kContiHead));
  write(folder / "scan_0001.csv", std::string(kContiHead));
  const InputError error =
      expect_input_error([&] { read_conti_radar(folder); }, (folder / "scan_0001.csv").string(), 0);
  EXPECT_THAT(error.what(), HasSubstr("YYYY-MM-DD-HH-MM-SS-fff.csv"));
}

}  // namespace
}  // namespace x2car::io

namespace x2car::io {
namespace {

// ---- issue 12: every wrong layout named, cluster lists, generic files found by their header ----

// Each layout's folder read as each other layout: an error that names the layout that reads it.
TEST(RadarLayouts, EveryWrongLayoutNamesTheOneThatReadsTheFiles) {
  const auto folder = temp_folder("every_wrong_layout");
  const std::vector<RadarLayout> layouts = {RadarLayout::kConti, RadarLayout::kDelphi,
                                            RadarLayout::kGeneric};
  for (const RadarLayout written : layouts) {
    write_radar(folder / to_string(written), written, sample_detections(), kStart);
    for (const RadarLayout given : layouts) {
      if (given == written) continue;
      SCOPED_TRACE(to_string(written) + " read as " + to_string(given));
      const InputError error =
          x2car::testing::input_error_of([&] { read_radar(folder / to_string(written), given); });
      EXPECT_THAT(error.what(), HasSubstr("look like the " + to_string(written) +
                                          " layout: pass --layout " + to_string(written)));
    }
  }
}

// A cluster list (no tracking): empty track id fields in every layout, read as kNoTrackId.
TEST(RadarLayouts, ClusterListsWithoutTrackIdsRoundTrip) {
  std::vector<RadarDetection> clusters = sample_detections();
  for (RadarDetection& d : clusters) {
    d.track_id = kNoTrackId;
    d.new_track = false;
  }
  for (const RadarLayout layout :
       {RadarLayout::kConti, RadarLayout::kDelphi, RadarLayout::kGeneric}) {
    SCOPED_TRACE(to_string(layout));
    const auto folder = temp_folder("clusters_" + to_string(layout));
    write_radar(folder / "radar", layout, clusters, kStart);
    const RadarLog log = read_radar(folder / "radar", RadarReadOptions{});
    EXPECT_EQ(log.layout, layout);
    ASSERT_EQ(log.detections.size(), clusters.size());
    for (std::size_t i = 0; i < clusters.size(); ++i) {
      EXPECT_EQ(log.detections[i].track_id, kNoTrackId);
      // Within a scan the writers keep the clusters' order.
      EXPECT_NEAR(log.detections[i].range, clusters[i].range, 1e-9);
    }
  }
  const std::string conti = format_conti_scan(std::span(clusters).first(3), 1);
  EXPECT_THAT(conti, HasSubstr("\n1,,"));
}

// A generic CSV under another name than detections.csv, alone in its folder, is found by its
// header; a folder of several is not guessed.
TEST(RadarLayouts, GenericCsvInAFolderIsFoundByItsHeader) {
  const auto folder = temp_folder("generic_by_header");
  write_radar_csv(folder / "radar_front.csv", sample_detections());
  EXPECT_EQ(detect_radar_layout(folder), RadarLayout::kGeneric);
  const RadarLog log = read_radar(folder, RadarReadOptions{});
  EXPECT_EQ(log.detections.size(), sample_detections().size());
  write_radar_csv(folder / "radar_rear.csv", sample_detections());
  const InputError error =
      x2car::testing::input_error_of([&] { read_radar(folder, RadarReadOptions{}); });
  EXPECT_THAT(error.what(), HasSubstr("detections.csv"));
}

}  // namespace
}  // namespace x2car::io
