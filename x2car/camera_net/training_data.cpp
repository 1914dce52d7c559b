#include "x2car/camera_net/training_data.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <array>
#include <atomic>
#include <cmath>
#include <mutex>

#include "x2car/camera/camera_frames.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/io/image_folder.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::camera_net {

std::vector<FrameLabelRow> read_frame_labels(const std::filesystem::path& path) {
  const std::string text = io::read_text_file(path);
  const std::vector<io::TextLine> lines = io::split_lines(text);
  const std::string file = path.string();
  if (lines.empty()) throw InputError(file, "is empty: expected a header and one row per frame");
  const std::vector<std::string_view> header = io::split_fields(lines.front().text);
  constexpr std::array<const char*, 4> kColumns = {"time", "road_vp_u_distorted",
                                                   "road_vp_v_distorted", "road_horizon_angle"};
  std::array<std::size_t, kColumns.size()> column{};
  for (std::size_t c = 0; c < kColumns.size(); ++c) {
    const auto found = std::find(header.begin(), header.end(), std::string_view(kColumns[c]));
    if (found == header.end()) {
      throw InputError(file, lines.front().number, kColumns[c],
                       "missing column (camera labels as x2car simulate writes them)");
    }
    column[c] = static_cast<std::size_t>(found - header.begin());
  }
  std::vector<FrameLabelRow> rows;
  rows.reserve(lines.size() - 1);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<std::string_view> fields =
        io::split_exact_fields(lines[i], header.size(), file, " (as many as the header names)");
    std::array<double, kColumns.size()> values{};
    for (std::size_t c = 0; c < kColumns.size(); ++c) {
      values[c] = io::parse_double(fields[column[c]], {file, lines[i].number, kColumns[c]});
    }
    rows.push_back({values[0], {values[1], values[2]}, values[3]});
  }
  return rows;
}

TrainingDriveIndex index_training_drive(const std::filesystem::path& drive) {
  const io::ImageFolder images = io::list_images(drive);
  const std::filesystem::path labels_path = drive / "camera" / "labels.csv";
  TrainingDriveIndex index;
  index.folder = drive;
  index.labels = read_frame_labels(labels_path);
  const std::vector<FrameLabelRow>& labels = index.labels;
  if (labels.size() != images.images.size()) {
    throw InputError(labels_path.string(),
                     fmt::format("has {} rows but {} holds {} images: every frame needs its label",
                                 labels.size(), images.folder.string(), images.images.size()));
  }
  // The labels count from the drive's start, the images carry its clock: compare the spacing.
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const double image_time = images.images[i].time - images.images.front().time;
    if (std::abs(image_time - (labels[i].time_s - labels.front().time_s)) > 1e-3) {
      throw InputError(labels_path.string(), i + 2, "time",
                       fmt::format("{} s after the first label, but image {} is {} s after the "
                                   "first image",
                                   labels[i].time_s - labels.front().time_s,
                                   images.images[i].path.filename().string(), image_time));
    }
    index.images.push_back(images.images[i].path);
  }
  return index;
}

TrainingDrive load_training_drive(const TrainingDriveIndex& index, const InputGeometry& geometry,
                                  int stride,
                                  const std::function<void(std::size_t, std::size_t)>& progress) {
  if (stride < 1) reject_argument("load_training_drive: stride must be >= 1 (got {})", stride);
  const std::vector<FrameLabelRow>& labels = index.labels;
  TrainingDrive result;
  result.folder = index.folder;
  std::vector<std::size_t> chosen;
  for (std::size_t i = 0; i < labels.size(); i += static_cast<std::size_t>(stride)) {
    chosen.push_back(i);
  }
  result.frames.resize(chosen.size());
  std::vector<cv::Size> sizes(chosen.size());
  std::atomic<std::size_t> done{0};
  std::mutex progress_mutex;
  tbb::parallel_for(std::size_t{0}, chosen.size(), [&](std::size_t k) {
    const std::size_t i = chosen[k];
    const cv::Mat grey = camera::read_grey_image(index.images[i]);
    sizes[k] = grey.size();
    LabelledFrame& frame = result.frames[k];
    frame.frame = make_input_frame(grey, geometry);
    frame.label.vanishing_point_px =
        input_from_image_px(labels[i].road_vanishing_point_px, grey.size(), geometry);
    frame.label.horizon_angle =
        input_from_image_angle(labels[i].road_horizon_angle, grey.size(), geometry);
    const std::size_t finished = ++done;
    if (progress) {
      const std::lock_guard<std::mutex> lock(progress_mutex);
      progress(finished, chosen.size());
    }
  });
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    if (sizes[k] != sizes.front()) {
      throw InputError(index.images[chosen[k]].string(),
                       fmt::format("is {}x{}, the drive's first image {}x{}", sizes[k].width,
                                   sizes[k].height, sizes.front().width, sizes.front().height));
    }
  }
  if (!sizes.empty()) result.image_size = sizes.front();
  return result;
}

}  // namespace x2car::camera_net
