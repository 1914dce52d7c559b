#include "x2car/camera/bag_frames.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/jpeg_data.hpp"
#include "x2car/io/ros_camera_info.hpp"
#include "x2car/io/ros_message.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::camera {
namespace {

constexpr const char* kImage = "sensor_msgs/Image";
constexpr const char* kCompressedImage = "sensor_msgs/CompressedImage";
constexpr const char* kCameraInfo = "sensor_msgs/CameraInfo";

bool is_image_type(const std::string& type) {
  return io::ros_type_is(type, kImage) || io::ros_type_is(type, kCompressedImage);
}

// The channels and OpenCV conversion to grey of a sensor_msgs/Image encoding (cv_bridge's Bayer
// names: ROS's bayer_rggb8 is OpenCV's BayerBG); conversion -1: already grey.
struct Encoding {
  int channels = 1;
  int bytes_per_channel = 1;
  int to_grey = -1;
};

std::optional<Encoding> encoding_of(const std::string& name) {
  static const std::map<std::string, Encoding> kEncodings = {
      {"mono8", {1, 1, -1}},
      {"8UC1", {1, 1, -1}},
      {"mono16", {1, 2, -1}},
      {"16UC1", {1, 2, -1}},
      {"rgb8", {3, 1, cv::COLOR_RGB2GRAY}},
      {"bgr8", {3, 1, cv::COLOR_BGR2GRAY}},
      {"8UC3", {3, 1, cv::COLOR_BGR2GRAY}},
      {"rgba8", {4, 1, cv::COLOR_RGBA2GRAY}},
      {"bgra8", {4, 1, cv::COLOR_BGRA2GRAY}},
      {"bayer_rggb8", {1, 1, cv::COLOR_BayerBG2GRAY}},
      {"bayer_bggr8", {1, 1, cv::COLOR_BayerRG2GRAY}},
      {"bayer_gbrg8", {1, 1, cv::COLOR_BayerGR2GRAY}},
      {"bayer_grbg8", {1, 1, cv::COLOR_BayerGB2GRAY}},
      {"yuv422", {2, 1, cv::COLOR_YUV2GRAY_UYVY}},
      {"uyvy", {2, 1, cv::COLOR_YUV2GRAY_UYVY}},
      {"yuv422_yuy2", {2, 1, cv::COLOR_YUV2GRAY_YUY2}},
      {"yuyv", {2, 1, cv::COLOR_YUV2GRAY_YUY2}},
  };
  const auto found = kEncodings.find(name);
  if (found == kEncodings.end()) return std::nullopt;
  return found->second;
}

// sensor_msgs/Image: header, height, width, encoding, is_bigendian, step, data.
cv::Mat decode_image(std::string_view bytes, io::RosEncoding encoding, const std::string& source) {
  io::RosMessageReader message(bytes, encoding, source);
  message.header();
  const std::uint32_t height = message.uint32("height");
  const std::uint32_t width = message.uint32("width");
  const std::string name = message.string("encoding");
  const bool big_endian = message.uint8("is_bigendian") != 0;
  const std::uint32_t step = message.uint32("step");
  const std::string_view data = message.byte_sequence("data");
  const std::optional<Encoding> format = encoding_of(name);
  if (!format) {
    throw InputError(source, 0, "encoding",
                     fmt::format("'{}': x2car reads mono8, mono16, rgb8, bgr8, rgba8, bgra8, "
                                 "bayer_*8 and yuv422 images",
                                 name));
  }
  const std::uint64_t row_bytes =
      static_cast<std::uint64_t>(width) * format->channels * format->bytes_per_channel;
  if (height == 0 || width == 0 || height > 65536 || width > 65536) {
    throw InputError(source, 0, "height, width", fmt::format("{} x {}", width, height));
  }
  if (step < row_bytes || static_cast<std::uint64_t>(step) * height > data.size()) {
    throw InputError(source, 0, "step",
                     fmt::format("{} bytes a row of {} x {} {} with {} bytes of data", step, width,
                                 height, name, data.size()));
  }
  const int type = CV_MAKETYPE(format->bytes_per_channel == 2 ? CV_16U : CV_8U, format->channels);
  // A view of the message's bytes; the conversions below copy.
  const cv::Mat view(static_cast<int>(height), static_cast<int>(width), type,
                     const_cast<char*>(data.data()), step);
  cv::Mat grey;
  if (format->bytes_per_channel == 2) {
    cv::Mat wide = view.clone();
    // The host is little-endian; a big-endian image's 16-bit values are swapped.
    if (big_endian) {
      wide.forEach<std::uint16_t>([](std::uint16_t& value, const int*) {
        value = static_cast<std::uint16_t>((value >> 8) | (value << 8));
      });
    }
    wide.convertTo(grey, CV_8U, 1.0 / 256.0);
  } else if (format->to_grey < 0) {
    grey = view.clone();
  } else {
    cv::cvtColor(view, grey, format->to_grey);
  }
  return grey;
}

// sensor_msgs/CompressedImage: header, format, data.
cv::Mat decode_compressed_image(std::string_view bytes, io::RosEncoding encoding,
                                const std::string& source) {
  io::RosMessageReader message(bytes, encoding, source);
  message.header();
  const std::string format = message.string("format");
  const std::string_view data = message.byte_sequence("data");
  if (const std::optional<std::string> cut =
          io::jpeg_cut_short({reinterpret_cast<const unsigned char*>(data.data()), data.size()})) {
    throw InputError(source, 0, "data", *cut);
  }
  cv::Mat grey;
  try {
    const cv::Mat encoded(1, static_cast<int>(data.size()), CV_8U, const_cast<char*>(data.data()));
    grey = cv::imdecode(encoded, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& error) {
    throw InputError(source, 0, "data", std::string("cannot be decoded: ") + error.what());
  }
  if (grey.empty()) {
    throw InputError(
        source, 0, "data",
        fmt::format("the '{}' image cannot be decoded (x2car reads JPEG and PNG)", format));
  }
  return grey;
}

// Whether a CompressedImage message's format names a lossy codec.
bool compressed_message_is_lossy(std::string_view bytes, io::RosEncoding encoding,
                                 const std::string& source) {
  io::RosMessageReader message(bytes, encoding, source);
  message.header();
  return compressed_image_format_is_lossy(message.string("format"));
}

// The namespace of a topic: all but its last name ("/camera" of "/camera/camera_info").
std::string namespace_of(const std::string& topic) {
  const std::size_t slash = topic.rfind('/');
  return slash == std::string::npos ? std::string() : topic.substr(0, slash);
}

}  // namespace

bool compressed_image_format_is_lossy(std::string_view format) {
  std::string lower(format);
  std::ranges::transform(lower, lower.begin(),
                         [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return lower.find("png") == std::string::npos;
}

BagFrames camera_frames_from_bag(const std::filesystem::path& path,
                                 const BagFrameOptions& options) {
  const std::string file = path.string();
  std::unique_ptr<io::BagFile> bag =
      io::open_bag(path, {.allow_truncated = options.allow_truncated});
  const auto chosen_topic = [&](const io::BagTopic& topic) {
    return options.topic ? topic.name == *options.topic : is_image_type(topic.type);
  };
  std::vector<std::vector<io::StampedMessage>> messages;
  std::map<std::size_t, std::string> first_info;  // CameraInfo topics: their first message
  std::vector<std::size_t> counts;
  std::map<std::size_t, std::string> frame_ids;  // per image topic: its first header.frame_id
  // The scan reads each frame's header alone where the container allows (64 KiB holds it, and a
  // CameraInfo message whole).
  constexpr std::size_t kHeaderBytes = 64 * 1024;
  bag->scan(
      [&](const io::BagTopic& topic) {
        return chosen_topic(topic) || io::ros_type_is(topic.type, kCameraInfo);
      },
      [&](const io::BagMessage& message) {
        messages.resize(bag->topics().size());
        counts.resize(bag->topics().size(), 0);
        const std::size_t count = ++counts[message.topic];
        const io::BagTopic& topic = bag->topics()[message.topic];
        if (io::ros_type_is(topic.type, kCameraInfo)) {
          if (!first_info.contains(message.topic)) {
            first_info[message.topic] = std::string(message.data);
          }
          return;
        }
        if (!chosen_topic(topic) || !is_image_type(topic.type)) return;
        const std::string source = fmt::format("{} ({} message {})", file, topic.name, count);
        const io::RosHeader header =
            io::RosMessageReader(message.data, io::ros_encoding_of(topic, path), source).header();
        frame_ids.emplace(message.topic, header.frame_id);
        messages[message.topic].push_back(
            {.stamp_ns = header.stamp_ns, .ref = message.ref, .count = count});
      },
      kHeaderBytes);

  const std::size_t chosen =
      io::choose_topic(*bag, options.topic, {kImage, kCompressedImage}, "image");
  const io::BagTopic topic = bag->topics()[chosen];
  std::vector<io::StampedMessage> frames =
      chosen < messages.size() ? std::move(messages[chosen]) : std::vector<io::StampedMessage>{};
  BagFrames out;
  out.source.times = io::order_by_stamp(frames, *bag, topic.name);
  out.topic = topic.name;
  out.frame_id = frame_ids.contains(chosen) ? frame_ids.at(chosen) : std::string();
  // The CameraInfo topic whose namespace holds the image topic, the deepest one.
  std::optional<std::size_t> info;
  for (const auto& [index, bytes] : first_info) {
    const std::string space = namespace_of(bag->topics()[index].name);
    if (!topic.name.starts_with(space + "/")) continue;
    if (!info || space.size() > namespace_of(bag->topics()[*info].name).size()) info = index;
  }
  if (info) {
    const io::BagTopic& info_topic = bag->topics()[*info];
    out.info_topic = info_topic.name;
    const bool rectified = topic.name.find("image_rect") != std::string::npos;
    out.intrinsics =
        io::decode_camera_info(first_info.at(*info), io::ros_encoding_of(info_topic, path),
                               fmt::format("{} ({} message 1)", file, info_topic.name), rectified)
            .intrinsics;
  }
  const io::RosEncoding encoding = io::ros_encoding_of(topic, path);
  const bool compressed = io::ros_type_is(topic.type, kCompressedImage);
  auto shared = std::make_shared<const std::vector<io::StampedMessage>>(std::move(frames));
  const auto name_of = [file, name = topic.name, shared](std::size_t index) {
    return fmt::format("{} ({} message {})", file, name, shared->at(index).count);
  };
  out.source.name = name_of;
  if (compressed && !shared->empty()) {
    // A first message that does not parse is reported when it is read (or skipped with
    // skip_bad_images); its topic is taken as JPEG's, as compressed camera topics mostly are.
    try {
      out.source.lossy =
          compressed_message_is_lossy(bag->read(shared->front().ref), encoding, name_of(0));
    } catch (const InputError&) {
      out.source.lossy = true;
    }
  }
  // Shared: the source may be copied, and outlives this call.
  out.source.read = [bag = std::shared_ptr<const io::BagFile>(std::move(bag)), shared, encoding,
                     compressed, name_of](std::size_t index) {
    const std::string bytes = bag->read(shared->at(index).ref);
    return compressed ? decode_compressed_image(bytes, encoding, name_of(index))
                      : decode_image(bytes, encoding, name_of(index));
  };
  return out;
}

}  // namespace x2car::camera
