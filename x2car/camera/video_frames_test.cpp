#include "x2car/camera/video_frames.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <vector>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::camera {
namespace {

namespace fs = std::filesystem;
using x2car::testing::AngleNearDeg;

// A file in this test run's temp folder (TEST_TMPDIR, one per build folder).
fs::path temp_path(const std::string& name) {
  const fs::path folder = fs::path(::testing::TempDir()) / "video_frames";
  fs::create_directories(folder);
  return folder / name;
}

const EulerAngles kVideoMounting{rad_from_deg(-1.0), rad_from_deg(2.0), rad_from_deg(1.5)};

// KITTI's camera with an even height: Motion-JPEG keeps whole 2x2 chroma blocks, so OpenCV's
// writer drops the odd 375th row.
core::CameraIntrinsics even_kitti() {
  core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  intrinsics.height = 376;
  return intrinsics;
}

cv::Mat street_frame(std::size_t index) {
  testing::StreetScene scene;
  scene.vehicle_from_camera = kVideoMounting;
  scene.road_heading = rad_from_deg(0.05) * std::sin(0.07 * static_cast<double>(index));
  scene.travelled_m = static_cast<double>(index);  // a car standing still would be refused
  scene.noise_seed = index + 1;
  return testing::draw_street(scene, even_kitti());
}

// A Motion-JPEG AVI (OpenCV writes it without any codec library) of `count` street frames.
fs::path write_street_video(const fs::path& path, std::size_t count, double rate_hz = 10.0) {
  const core::CameraIntrinsics kitti = even_kitti();
  cv::VideoWriter writer(path.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), rate_hz,
                         cv::Size(kitti.width, kitti.height), false);
  EXPECT_TRUE(writer.isOpened());
  for (std::size_t i = 0; i < count; ++i) writer.write(street_frame(i));
  writer.release();
  return path;
}

TEST(VideoFrames, TimesFromTheFrameRateAndFramesInAnyOrder) {
  const fs::path video = write_street_video(temp_path("street.avi"), 12);
  const VideoFrames found = camera_frames_from_video(video);
  const CameraFrameSource& frames = found.source;
  ASSERT_EQ(frames.times.size(), 12U);
  EXPECT_DOUBLE_EQ(frames.times[0], 0.0);
  EXPECT_NEAR(frames.times[11], 1.1, 1e-9);
  EXPECT_EQ(found.time_source, "the video's frame times");
  EXPECT_NEAR(found.mean_frame_rate_hz, 10.0, 1e-9);
  EXPECT_EQ(found.container_frames, 12U);
  EXPECT_TRUE(found.notes.empty());
  // Forward, back beyond a small cache (reopens), and again: the same pixels each time.
  VideoFrameOptions small_cache;
  small_cache.cached_frames = 2;
  const CameraFrameSource reread = camera_frames_from_video(video, small_cache).source;
  const cv::Mat tenth = frames.read(10);
  EXPECT_EQ(tenth.type(), CV_8UC1);
  for (const std::size_t index : {10U, 3U, 4U, 11U, 0U, 10U}) {
    const cv::Mat image = reread.read(index);
    ASSERT_EQ(image.size(), tenth.size());
    if (index == 10U) {
      EXPECT_EQ(cv::norm(image, tenth, cv::NORM_INF), 0.0);
    }
  }
  EXPECT_THROW(reread.read(12), InputError);
  EXPECT_NE(frames.name(3).find("street.avi frame 3"), std::string::npos);
  EXPECT_TRUE(frames.lossy);  // a camera's video is coded with loss
}

// Read at most 10 Hz of a 30 Hz video (every 3rd frame), the decoder keeps those alone: a cache
// of 2 holds the last two read, 6 frames back, and every frame, on the stride or not, forward or
// back, is the frame the plain source gives.
TEST(VideoFrames, KeepsTheFramesTheCalibratorReadsAtAMostRate) {
  const fs::path video = write_street_video(temp_path("street_30_hz.avi"), 16, 30.0);
  const CameraFrameSource every = camera_frames_from_video(video).source;
  VideoFrameOptions strided;
  strided.cached_frames = 2;
  strided.max_frame_rate_hz = 10.0;
  const CameraFrameSource kept = camera_frames_from_video(video, strided).source;
  for (const std::size_t index : {0U, 3U, 6U, 9U, 12U, 9U, 6U, 7U, 15U, 13U, 1U}) {
    EXPECT_EQ(cv::norm(kept.read(index), every.read(index), cv::NORM_INF), 0.0) << index;
  }
  strided.max_frame_rate_hz = -1.0;
  EXPECT_THROW(camera_frames_from_video(video, strided), std::invalid_argument);
}

TEST(VideoFrames, CalibratesLikeTheImages) {
  const fs::path video = write_street_video(temp_path("drive.avi"), 30);
  CameraCalibrationOptions options;
  options.filter.window_frames = 10;
  const CalibrationResult result =
      calibrate_camera(camera_frames_from_video(video).source, even_kitti(), options);
  ASSERT_TRUE(result.ok()) << result.reason;
  EXPECT_THAT(*result.roll, AngleNearDeg(kVideoMounting.roll, 0.1));
  EXPECT_THAT(*result.pitch, AngleNearDeg(kVideoMounting.pitch, 0.1));
  EXPECT_THAT(*result.yaw, AngleNearDeg(kVideoMounting.yaw, 0.1));
}

TEST(VideoFrames, TimestampsFileAndFrameRate) {
  const fs::path video = write_street_video(temp_path("timed.avi"), 3);
  const fs::path times = temp_path("timed.txt");
  std::ofstream(times) << "100.0\n100.05\n100.1\n";
  VideoFrameOptions options;
  options.timestamps = times;
  EXPECT_NEAR(camera_frames_from_video(video, options).source.times[1], 100.05, 1e-9);
  std::ofstream(times) << "100.0\n100.05\n";
  try {
    camera_frames_from_video(video, options);
    FAIL() << "a timestamps file with too few lines was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("holds 2 timestamps"), std::string::npos);
  }
  VideoFrameOptions rate;
  rate.frame_rate_hz = 20.0;
  EXPECT_NEAR(camera_frames_from_video(video, rate).source.times[2], 0.1, 1e-9);
  rate.frame_rate_hz = -1.0;
  EXPECT_THROW(camera_frames_from_video(video, rate), std::invalid_argument);
  // Both give the times: the frame rate was silently ignored.
  options.frame_rate_hz = 20.0;
  EXPECT_THROW(camera_frames_from_video(video, options), std::invalid_argument);
}

// An H.264 MP4 (the common camera video): the decoder gives its last frames, held for reordering
// (one per frame thread, as many as the machine's cores), without a time; they are spaced as the
// frames before, and the times need no note.
TEST(VideoFrames, TimesAnH264VideoByItsFramesTimes) {
  const fs::path path = temp_path("moving_h264.mp4");
  cv::VideoWriter writer(path.string(), cv::CAP_FFMPEG, cv::VideoWriter::fourcc('a', 'v', 'c', '1'),
                         12.5, cv::Size(320, 240), false);
  if (!writer.isOpened()) GTEST_SKIP() << "this OpenCV writes no H.264";
  constexpr std::size_t kFrames = 300;
  for (std::size_t i = 0; i < kFrames; ++i) {
    cv::Mat frame(240, 320, CV_8UC1, cv::Scalar(60));
    cv::circle(frame, {static_cast<int>(i % 300), 120}, 30, cv::Scalar(220), -1);
    writer.write(frame);
  }
  writer.release();
  const VideoFrames video = camera_frames_from_video(path);
  ASSERT_EQ(video.source.times.size(), kFrames);
  for (std::size_t i = 0; i < kFrames; ++i) {
    EXPECT_NEAR(video.source.times[i], 0.08 * static_cast<double>(i), 1e-6) << i;
  }
  EXPECT_EQ(video.time_source.rfind("the video's frame times", 0), 0U) << video.time_source;
  EXPECT_NEAR(video.mean_frame_rate_hz, 12.5, 1e-6);
  EXPECT_TRUE(video.notes.empty());
}

// The container's times: the trailing frames that read 0 are re-spaced, however many (an H.264
// decoder with 40 threads holds 40); a time that repeats or goes back is not re-spaced, which
// would shift every later frame (nullopt: the nominal rate and a note).
TEST(VideoFrames, FrameTimesFromTheContainer) {
  std::size_t flushed = 0;
  std::vector<double> read = {5.0, 5.1, 5.2};
  read.resize(43, 0.0);
  const std::optional<std::vector<double>> respaced = frame_times_from_container(read, flushed);
  ASSERT_TRUE(respaced.has_value());
  EXPECT_EQ(flushed, 40U);
  EXPECT_NEAR(respaced->back(), 4.2, 1e-9);
  EXPECT_TRUE(frame_times_from_container({0.0, 0.1}, flushed).has_value());  // two frames
  EXPECT_FALSE(frame_times_from_container({0.0, 0.1, 0.1, 0.3, 0.0}, flushed).has_value());
  EXPECT_FALSE(frame_times_from_container({0.0, 0.2, 0.1, 0.3}, flushed).has_value());
  EXPECT_FALSE(frame_times_from_container({0.0, 0.0, 0.0}, flushed).has_value());
  EXPECT_FALSE(frame_times_from_container({0.0, NAN, 0.3}, flushed).has_value());
  // A variable rate keeps its times.
  EXPECT_EQ(frame_times_from_container({1.0, 1.1, 1.15, 1.3}, flushed),
            (std::vector<double>{0.0, 1.1 - 1.0, 1.15 - 1.0, 1.3 - 1.0}));
}

// A video cut short (a recording that stopped, a copy that did not finish) decodes fewer frames
// than its container lists: it is calibrated, and the note says so (it was silently shortened).
TEST(VideoFrames, ATruncatedVideoSaysWhereDecodingStopped) {
  const fs::path whole = write_street_video(temp_path("whole.avi"), 40);
  const fs::path cut = temp_path("cut.avi");
  fs::copy_file(whole, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(whole) / 2);
  const VideoFrames video = camera_frames_from_video(cut);
  EXPECT_GT(video.source.times.size(), 5U);
  EXPECT_LT(video.source.times.size(), 30U);
  ASSERT_EQ(video.notes.size(), 1U);
  EXPECT_NE(video.notes[0].find("decoding stopped after"), std::string::npos) << video.notes[0];
  EXPECT_NE(video.notes[0].find("of the 40 frames"), std::string::npos) << video.notes[0];
  EXPECT_NE(video.notes[0].find("cut.avi"), std::string::npos) << video.notes[0];
}

TEST(VideoFrames, OpensARelativeNameWithAColon) {
  // FFmpeg took "2024-05-01T10:00:00.avi" for a URL whose scheme is "2024-05-01T10".
  const fs::path video = write_street_video(temp_path("2024-05-01T10:00:00.avi"), 3);
  const fs::path before = fs::current_path();
  fs::current_path(video.parent_path());
  std::size_t count = 0;
  try {
    count = camera_frames_from_video(video.filename()).source.times.size();
  } catch (const InputError& error) {
    ADD_FAILURE() << error.what();
  }
  fs::current_path(before);
  EXPECT_EQ(count, 3U);
}

TEST(VideoFrames, MissingOrBrokenFilesNameTheFile) {
  const fs::path missing = temp_path("missing.mp4");
  const fs::path text = temp_path("not_a_video.avi");
  std::ofstream(text) << "this is not a video\n";
  for (const fs::path& path : {missing, text}) {
    try {
      camera_frames_from_video(path);
      FAIL() << path;
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(path.filename().string()), std::string::npos);
      if (path == missing) {  // said plainly, not "cannot be opened as a video"
        EXPECT_NE(std::string(error.what()).find("does not exist"), std::string::npos);
      }
    }
  }
  EXPECT_TRUE(is_video_file("a/b.MP4"));
  EXPECT_TRUE(is_video_file("drive.mkv"));
  EXPECT_FALSE(is_video_file("drive"));
  EXPECT_FALSE(is_video_file("frame.png"));
}

}  // namespace
}  // namespace x2car::camera
