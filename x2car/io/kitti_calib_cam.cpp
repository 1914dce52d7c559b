#include "x2car/io/kitti_calib_cam.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using core::CameraIntrinsics;
using core::DistortionModel;

void check_index(int camera_index) {
  if (camera_index < 0 || camera_index > 9) {
    throw std::invalid_argument(
        fmt::format("KITTI camera index must be in [0, 9], found {}", camera_index));
  }
}

std::string numbers(const std::vector<double>& values) {
  std::string text;
  for (const double value : values) text += (text.empty() ? "" : " ") + format_number(value);
  return text;
}

struct Entry {
  std::size_t line = 0;
  std::string_view value;  // after the colon
};

// The camera's entries by key, each at most once.
class Entries {
 public:
  Entries(std::string_view text, std::string source, std::string suffix)
      : source_(std::move(source)), suffix_(std::move(suffix)) {
    for (const TextLine& line : split_lines(text)) {
      const std::size_t colon = line.text.find(':');
      if (colon == std::string_view::npos) continue;
      const std::string key(trim(line.text.substr(0, colon)));
      if (key.size() > 3 && key[key.size() - 3] == '_' && key[key.size() - 2] == '0' &&
          std::isdigit(static_cast<unsigned char>(key.back())) != 0) {
        cameras_.insert(key.substr(key.size() - 2));
      }
      if (!key.ends_with(suffix_)) continue;
      if (entries_.contains(key)) {
        throw InputError(source_, line.number, key,
                         fmt::format("given twice (first on line {})", entries_[key].line));
      }
      entries_[key] = {line.number, trim(line.text.substr(colon + 1))};
    }
  }

  bool has(const std::string& name) const { return entries_.contains(name + suffix_); }

  // "missing key", and which cameras the file holds when it holds none of this one's keys (a KITTI
  // file has cameras 00-03; --camera-index picks one).
  std::string missing_key_message() const {
    if (!entries_.empty() || cameras_.empty()) return "missing key";
    std::string held;
    for (const std::string& camera : cameras_) held += (held.empty() ? "" : ", ") + camera;
    return fmt::format("missing key: the file holds no camera {} (its cameras: {})",
                       suffix_.substr(1), held);
  }

  // The numbers of NAME_0X; `counts` lists the counts allowed.
  std::vector<double> values(const std::string& name, std::initializer_list<std::size_t> counts,
                             std::size_t* line_out = nullptr) const {
    const std::string key = name + suffix_;
    const auto it = entries_.find(key);
    if (it == entries_.end()) throw InputError(source_, 0, key, missing_key_message());
    const Entry& entry = it->second;
    if (line_out) *line_out = entry.line;
    std::vector<double> parsed;
    const std::vector<std::string_view> fields = split_fields(entry.value);
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (fields[i].empty()) continue;
      parsed.push_back(
          parse_double(fields[i], {source_, entry.line, fmt::format("{}[{}]", key, i)}));
    }
    if (std::find(counts.begin(), counts.end(), parsed.size()) == counts.end()) {
      throw InputError(
          source_, entry.line, key,
          fmt::format("expected {} numbers, found {}", *counts.begin(), parsed.size()));
    }
    return parsed;
  }

  std::string text(const std::string& name) const {
    const auto it = entries_.find(name + suffix_);
    return it == entries_.end() ? std::string() : std::string(it->second.value);
  }
  std::size_t line(const std::string& name) const {
    const auto it = entries_.find(name + suffix_);
    return it == entries_.end() ? 0 : it->second.line;
  }

  // Width and height from NAME_0X ("1.242000e+03 3.750000e+02").
  void image_size(const std::string& name, CameraIntrinsics& c) const {
    std::size_t line = 0;
    const std::vector<double> size = values(name, {2}, &line);
    for (int i = 0; i < 2; ++i) {
      const double value = size[static_cast<std::size_t>(i)];
      if (value != std::floor(value) || value < 1.0 || value > 1e6) {
        throw InputError(source_, line, fmt::format("{}{}[{}]", name, suffix_, i),
                         fmt::format("expected a positive whole number of pixels, found {}",
                                     format_number(value)));
      }
    }
    c.width = static_cast<int>(size[0]);
    c.height = static_cast<int>(size[1]);
  }

  // fx, fy, cx, cy from the 3x3 part of a row-major matrix with `cols` columns (3 for K, 4 for P).
  void pinhole(const std::string& name, int cols, CameraIntrinsics& c) const {
    std::size_t line = 0;
    const std::vector<double> m = values(name, {static_cast<std::size_t>(3 * cols)}, &line);
    const auto at = [&](int row, int col) { return m[static_cast<std::size_t>(row * cols + col)]; };
    if (at(0, 1) != 0.0 || at(1, 0) != 0.0 || at(2, 0) != 0.0 || at(2, 1) != 0.0 ||
        at(2, 2) != 1.0) {
      throw InputError(source_, line, name + suffix_,
                       "expected a camera matrix [fx 0 cx; 0 fy cy; 0 0 1] (no skew)");
    }
    c.fx = at(0, 0);
    c.cx = at(0, 2);
    c.fy = at(1, 1);
    c.cy = at(1, 2);
    if (const std::optional<core::PinholeProblem> problem = core::pinhole_problem(c)) {
      throw InputError(source_, line,
                       fmt::format("{}{}[{}]", name, suffix_, problem->matrix_index(cols)),
                       problem->why);
    }
  }

  const std::string& source() const { return source_; }

 private:
  std::string source_;
  std::string suffix_;             // "_02"
  std::set<std::string> cameras_;  // "00", "02", ...: the suffixes of the file's keys
  std::map<std::string, Entry> entries_;
};

}  // namespace

std::string format_kitti_calib_cam(const CameraIntrinsics& c, int camera_index,
                                   std::string_view calib_time) {
  c.Check();
  check_index(camera_index);
  const std::string x = fmt::format("0{}", camera_index);
  const bool none = c.distortion_model == DistortionModel::kNone;
  const std::vector<double> d = none ? std::vector<double>(5, 0.0) : c.distortion_coefficients;
  const std::vector<double> size{static_cast<double>(c.width), static_cast<double>(c.height)};
  const std::vector<double> identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::string text = fmt::format("calib_time: {}\ncorner_dist: 0\n", calib_time);
  text += fmt::format("S_{}: {}\n", x, numbers(size));
  text += fmt::format("K_{}: {}\n", x, numbers({c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1}));
  text += fmt::format("D_{}: {}\n", x, numbers(d));
  if (c.distortion_model == DistortionModel::kEquidistant) {
    text += fmt::format("distortion_model_{}: equidistant\n", x);
  }
  text += fmt::format("R_{}: {}\nT_{}: 0 0 0\n", x, numbers(identity), x);
  text += fmt::format("S_rect_{}: {}\nR_rect_{}: {}\n", x, numbers(size), x, numbers(identity));
  text +=
      fmt::format("P_rect_{}: {}\n", x, numbers({c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0}));
  return text;
}

void write_kitti_calib_cam(const std::filesystem::path& path, const CameraIntrinsics& intrinsics,
                           int camera_index, std::string_view calib_time) {
  write_text_file(path, format_kitti_calib_cam(intrinsics, camera_index, calib_time));
}

CameraIntrinsics read_kitti_calib_cam(const std::filesystem::path& path, int camera_index,
                                      KittiImages images) {
  return parse_kitti_calib_cam(read_text_file(path), path.string(), camera_index, images);
}

CameraIntrinsics parse_kitti_calib_cam(std::string_view text, const std::string& source_name,
                                       int camera_index, KittiImages images) {
  check_index(camera_index);
  const Entries entries(text, source_name, fmt::format("_0{}", camera_index));
  CameraIntrinsics c;
  if (images == KittiImages::kRectified) {
    entries.image_size("S_rect", c);
    entries.pinhole("P_rect", 4, c);
  } else {
    entries.image_size("S", c);
    entries.pinhole("K", 3, c);
    const std::string model = entries.text("distortion_model");
    if (!model.empty() && model != "equidistant" && model != "plumb_bob") {
      throw InputError(source_name, entries.line("distortion_model"),
                       fmt::format("distortion_model_0{}", camera_index),
                       "expected plumb_bob or equidistant, found " + quote_field(model));
    }
    if (model == "equidistant") {
      c.distortion_model = DistortionModel::kEquidistant;
      c.distortion_coefficients = entries.values("D", {4});
    } else {
      std::vector<double> d = entries.values("D", {5, 4});
      d.resize(5, 0.0);
      if (std::any_of(d.begin(), d.end(), [](double v) { return v != 0.0; })) {
        c.distortion_model = DistortionModel::kPlumbBob;
        c.distortion_coefficients = std::move(d);
      }
    }
  }
  try {
    c.Check();
  } catch (const std::invalid_argument& error) {
    throw InputError(source_name, error.what());
  }
  return c;
}

}  // namespace x2car::io
