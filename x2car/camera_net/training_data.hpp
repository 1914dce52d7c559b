// The network's training and evaluation data: simulated drives (`x2car simulate --sensors camera`)
// with their images and `camera/labels.csv` (docs/simulator.md), read into network inputs.
//
// Labels: the road's vanishing point as the raw (distorted) image shows it
// (road_vp_u_distorted, road_vp_v_distorted) and the road plane's horizon angle
// (road_horizon_angle): the car's horizon, not gravity's, so that what the network learns is the
// mounting's roll whatever the road's crossfall (docs/methods.md, camera §4).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "x2car/camera_net/network_input.hpp"

namespace x2car::camera_net {

struct LabelledFrame {
  InputFrame frame;
  InputLabel label;
};

struct TrainingDrive {
  std::filesystem::path folder;
  cv::Size image_size;  // the camera's full image size
  std::vector<LabelledFrame> frames;
};

// One row of camera/labels.csv, the columns the network needs.
struct FrameLabelRow {
  double time_s = 0.0;
  Eigen::Vector2d road_vanishing_point_px = Eigen::Vector2d::Zero();  // distorted image
  double road_horizon_angle = 0.0;                                    // [rad]
};

// Reads a labels.csv by column names; InputError naming the file, line and column.
std::vector<FrameLabelRow> read_frame_labels(const std::filesystem::path& path);

// A drive folder's images and their labels, checked against each other but not decoded.
struct TrainingDriveIndex {
  std::filesystem::path folder;
  std::vector<std::filesystem::path> images;  // in time order
  std::vector<FrameLabelRow> labels;          // one per image
};

// Lists a drive folder (DIR/camera/images, timestamps.txt, labels.csv). InputError naming the file
// when images and labels disagree in number or time, or either is missing or broken.
TrainingDriveIndex index_training_drive(const std::filesystem::path& drive);

// Every `stride`-th frame of an indexed drive decoded, resampled and lined (make_input_frame) in
// parallel. InputError naming the image when it cannot be decoded or its size differs from the
// first's. `progress(done, total)`, when given, is called from one thread at a time.
TrainingDrive load_training_drive(
    const TrainingDriveIndex& index, const InputGeometry& geometry, int stride = 1,
    const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace x2car::camera_net
