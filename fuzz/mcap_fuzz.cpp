// libFuzzer target for the MCAP reader (io/mcap_reader.hpp): records, chunks (lz4, zstd, none),
// CRCs, truncation. Every input is read with and without allow_truncated, every handler set, and
// each message's bytes touched (they must lie inside what was read); then read as a GNSS/INS log
// from its Odometry topic (io/bag_ins.hpp), whose records must be finite.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz/fuzz_support.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/bag_ins.hpp"
#include "x2car/io/bag_radar.hpp"
#include "x2car/io/bag_tf.hpp"
#include "x2car/io/mcap_reader.hpp"
#include "x2car/io/ros_camera_info.hpp"
#include "x2car/io/ros_point_cloud2.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace x2car;
  const std::filesystem::path path = fuzz::scratch_folder() / "fuzz.mcap";
  fuzz::write_scratch_file(path, fuzz::as_text(data, size));
  std::uint64_t checksum = 0;
  io::McapHandlers handlers;
  handlers.on_schema = [&](const io::McapSchema& schema) { checksum += schema.data.size(); };
  handlers.on_channel = [&](const io::McapChannel& channel) {
    checksum += channel.topic.size() + channel.metadata.size();
  };
  handlers.on_message = [&](const io::McapMessage& message) {
    for (const char byte : message.data) checksum += static_cast<unsigned char>(byte);
  };
  for (const bool allow_truncated : {false, true}) {
    fuzz::accept_input_errors(
        "read_mcap", [&] { io::read_mcap(path, handlers, {.allow_truncated = allow_truncated}); });
  }
  // Chunks read only as far as their message indexes say the wanted prefixes reach, and the
  // messages read again by their offsets.
  fuzz::accept_input_errors("read_mcap prefix", [&] {
    std::vector<io::McapMessage> refs;
    io::McapHandlers prefix_handlers = handlers;
    prefix_handlers.on_message = [&](const io::McapMessage& message) {
      if (message.chunk_offset != 0 && !message.data.empty()) refs.push_back(message);
    };
    io::read_mcap(path, prefix_handlers,
                  {.data_prefix = 4, .wants_data = [](std::uint16_t id) { return id % 2 == 0; }});
    for (const io::McapMessage& message : refs) {
      checksum +=
          io::read_mcap_message(path, message.chunk_offset, message.data_offset, message.data_size)
              .size();
    }
  });
  // A GNSS/INS log from its Odometry topic: ROS 2 CDR decoding (ros_message.hpp, bag_ins.hpp).
  fuzz::accept_input_errors("read_ins_bag", [&] {
    for (const io::InsRecord& record : io::read_ins_bag(path).records) {
      fuzz::expect_finite(record.time, "read_ins_bag time");
      fuzz::expect_finite(record.attitude.yaw, "read_ins_bag yaw");
      fuzz::expect_finite(record.velocity_enu.x(), "read_ins_bag velocity");
    }
  });
  // Every message as every type x2car decodes, in both encodings; then read back by reference.
  fuzz::accept_input_errors("open_bag", [&] {
    const auto bag = io::open_bag(path, {.allow_truncated = true});
    std::vector<io::BagMessageRef> refs;
    bag->scan({}, [&](const io::BagMessage& message) {
      refs.push_back(message.ref);
      for (const io::RosEncoding encoding : {io::RosEncoding::kCdr, io::RosEncoding::kRos1}) {
        fuzz::accept_input_errors("decode_point_cloud2", [&] {
          for (const io::LidarPoint& point :
               io::decode_point_cloud2(message.data, encoding, "m").cloud.points) {
            checksum += point.ring;
          }
        });
        fuzz::accept_input_errors("decode_camera_info", [&] {
          const auto info = io::decode_camera_info(message.data, encoding, "m");
          fuzz::expect_finite(info.intrinsics.fx, "decode_camera_info fx");
        });
      }
    });
    for (const io::BagMessageRef& ref : refs) checksum += bag->read(ref).size();
  });
  fuzz::accept_input_errors("read_radar_bag", [&] {
    for (const io::RadarDetection& detection : io::read_radar_bag(path).detections) {
      fuzz::expect_finite(detection.range_rate, "read_radar_bag range_rate");
    }
  });
  fuzz::accept_input_errors("read_bag_transforms",
                            [&] { checksum += io::read_bag_transforms(path).size(); });
  return checksum == 1 ? 1 : 0;  // keeps the reads; libFuzzer ignores the value
}
