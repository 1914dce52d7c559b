#include "x2car/io/ros_point_cloud2.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <type_traits>
#include <vector>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

// sensor_msgs/PointField datatypes.
enum Datatype : std::uint8_t {
  kInt8 = 1,
  kUint8 = 2,
  kInt16 = 3,
  kUint16 = 4,
  kInt32 = 5,
  kUint32 = 6,
  kFloat32 = 7,
  kFloat64 = 8,
};

std::size_t size_of(std::uint8_t datatype) {
  switch (datatype) {
    case kInt8:
    case kUint8:
      return 1;
    case kInt16:
    case kUint16:
      return 2;
    case kInt32:
    case kUint32:
    case kFloat32:
      return 4;
    case kFloat64:
      return 8;
    default:
      return 0;
  }
}

bool is_float(std::uint8_t datatype) { return datatype == kFloat32 || datatype == kFloat64; }

struct Field {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
};

template <typename Unsigned>
Unsigned load(const char* at, bool big_endian) {
  std::array<char, sizeof(Unsigned)> bytes;
  std::memcpy(bytes.data(), at, bytes.size());
  if (big_endian) std::ranges::reverse(bytes);
  return std::bit_cast<Unsigned>(bytes);
}

// Calls `store(index, value)` for every point of the cloud, `value` the field's in its own type:
// one switch per field, then a tight loop (a sweep has ~100 k points; a switch per point and value
// made decoding slower than reading a PCD file).
template <typename T, typename Store>
void for_each_typed(const char* data, std::uint32_t height, std::uint32_t width,
                    std::uint32_t row_step, std::uint32_t point_step, std::uint32_t offset,
                    bool big_endian, Store& store) {
  using Raw = std::conditional_t<
      sizeof(T) == 1, std::uint8_t,
      std::conditional_t<sizeof(T) == 2, std::uint16_t,
                         std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  std::size_t index = 0;
  for (std::uint32_t row = 0; row < height; ++row) {
    const char* at = data + static_cast<std::size_t>(row) * row_step + offset;
    for (std::uint32_t column = 0; column < width; ++column, ++index, at += point_step) {
      store(index, std::bit_cast<T>(load<Raw>(at, big_endian)));
    }
  }
}

const Field* find_field(const std::vector<Field>& fields,
                        std::initializer_list<std::string_view> names) {
  for (const std::string_view name : names) {
    for (const Field& field : fields) {
      if (field.name == name) return &field;
    }
  }
  return nullptr;
}

struct Layout {
  std::uint32_t height = 0;
  std::uint32_t width = 0;
  std::vector<Field> fields;
  bool big_endian = false;
  std::uint32_t point_step = 0;
  std::uint32_t row_step = 0;
  std::string_view data;
};

template <typename Store>
void for_each_value(const Layout& layout, const Field& field, Store&& store) {
  const auto run = [&]<typename T>(T) {
    for_each_typed<T>(layout.data.data(), layout.height, layout.width, layout.row_step,
                      layout.point_step, field.offset, layout.big_endian, store);
  };
  switch (field.datatype) {
    case kInt8:
      return run(std::int8_t{});
    case kUint8:
      return run(std::uint8_t{});
    case kInt16:
      return run(std::int16_t{});
    case kUint16:
      return run(std::uint16_t{});
    case kInt32:
      return run(std::int32_t{});
    case kUint32:
      return run(std::uint32_t{});
    case kFloat32:
      return run(float{});
    default:
      return run(double{});
  }
}

Layout read_layout(RosMessageReader& message, const std::string& source) {
  Layout layout;
  layout.height = message.uint32("height");
  layout.width = message.uint32("width");
  const std::uint32_t field_count = message.uint32("fields");
  if (field_count > 1024) {
    throw InputError(source, 0, "fields",
                     fmt::format("{} fields: not a point layout", field_count));
  }
  for (std::uint32_t i = 0; i < field_count; ++i) {
    Field field;
    field.name = message.string("fields.name");
    field.offset = message.uint32("fields.offset");
    field.datatype = message.uint8("fields.datatype");
    const std::uint32_t count = message.uint32("fields.count");
    if (size_of(field.datatype) == 0) {
      throw InputError(
          source, 0, "fields." + field.name,
          fmt::format("datatype {} is not a PointField type (1 to 8)", field.datatype));
    }
    (void)count;  // arrays (count > 1) are allowed for fields x2car does not use
    layout.fields.push_back(std::move(field));
  }
  layout.big_endian = message.boolean("is_bigendian");
  layout.point_step = message.uint32("point_step");
  layout.row_step = message.uint32("row_step");
  layout.data = message.byte_sequence("data");
  message.boolean("is_dense");

  for (const Field& field : layout.fields) {
    if (static_cast<std::uint64_t>(field.offset) + size_of(field.datatype) > layout.point_step) {
      throw InputError(source, 0, "fields." + field.name,
                       fmt::format("offset {} + {} bytes lies past point_step {}", field.offset,
                                   size_of(field.datatype), layout.point_step));
    }
  }
  if (static_cast<std::uint64_t>(layout.width) * layout.point_step > layout.row_step) {
    throw InputError(source, 0, "row_step",
                     fmt::format("{} is less than width {} x point_step {}", layout.row_step,
                                 layout.width, layout.point_step));
  }
  const std::uint64_t needed = static_cast<std::uint64_t>(layout.height) * layout.row_step;
  if (needed > layout.data.size()) {
    throw InputError(source, 0, "data",
                     fmt::format("holds {} bytes; height {} x row_step {} needs {}",
                                 layout.data.size(), layout.height, layout.row_step, needed));
  }
  return layout;
}

// How a time field's values become seconds since header.stamp.
struct TimeScale {
  double scale = 1.0;   // to seconds
  double offset = 0.0;  // subtracted after scaling [s]
};

TimeScale time_scale(const Layout& layout, const Field& field, std::int64_t stamp_ns,
                     const std::string& source) {
  if (field.name != "timestamp") {
    return {.scale = is_float(field.datatype) ? 1.0 : 1e-9, .offset = 0.0};
  }
  // Absolute stamps: seconds when every value lies within a minute of the header's stamp, else
  // nanoseconds when they do so read (near a clock's zero both may: a sweep's nanoseconds span
  // millions, so seconds are the reading that fits then).
  constexpr double kWithin = 60.0;  // [s]
  const double stamp_s = static_cast<double>(stamp_ns) * 1e-9;
  double farthest_as_seconds = 0.0;
  double farthest_as_nanoseconds = 0.0;
  for_each_value(layout, field, [&](std::size_t, auto typed) {
    const auto value = static_cast<double>(typed);
    if (!std::isfinite(value)) return;
    farthest_as_seconds = std::max(farthest_as_seconds, std::abs(value - stamp_s));
    farthest_as_nanoseconds = std::max(farthest_as_nanoseconds, std::abs(value * 1e-9 - stamp_s));
  });
  if (farthest_as_seconds <= kWithin) return {.scale = 1.0, .offset = stamp_s};
  if (farthest_as_nanoseconds <= kWithin) return {.scale = 1e-9, .offset = stamp_s};
  throw InputError(source, 0, "fields.timestamp",
                   fmt::format("values lie more than {} s from header.stamp {} s, read as seconds "
                               "and as nanoseconds",
                               kWithin, stamp_s));
}

}  // namespace

RosHeader read_point_cloud2_header(std::string_view bytes, RosEncoding encoding,
                                   const std::string& source) {
  RosMessageReader message(bytes, encoding, source);
  return message.header();
}

StampedPointCloud decode_point_cloud2(std::string_view bytes, RosEncoding encoding,
                                      const std::string& source) {
  RosMessageReader message(bytes, encoding, source);
  StampedPointCloud out;
  out.header = message.header();
  const Layout layout = read_layout(message, source);
  const Field* x = find_field(layout.fields, {"x"});
  const Field* y = find_field(layout.fields, {"y"});
  const Field* z = find_field(layout.fields, {"z"});
  for (const auto& [field, name] : {std::pair{x, "x"}, std::pair{y, "y"}, std::pair{z, "z"}}) {
    if (field == nullptr) throw InputError(source, 0, "fields", fmt::format("no field {}", name));
    if (!is_float(field->datatype)) {
      throw InputError(source, 0, std::string("fields.") + name,
                       "is not FLOAT32 or FLOAT64 (datatype 7 or 8)");
    }
  }
  const Field* intensity = find_field(layout.fields, {"intensity", "i", "reflectivity"});
  const Field* ring = find_field(layout.fields, {"ring", "line", "laser_id", "channel"});
  if (ring != nullptr && is_float(ring->datatype)) {
    throw InputError(source, 0, "fields." + ring->name, "a beam index of a float type");
  }
  const Field* time = find_field(layout.fields, {"t", "time", "offset_time", "timestamp"});
  const TimeScale scale =
      time == nullptr ? TimeScale{} : time_scale(layout, *time, out.header.stamp_ns, source);

  PointCloud& cloud = out.cloud;
  cloud.has_intensity = intensity != nullptr;
  cloud.has_ring = ring != nullptr;
  cloud.has_time = time != nullptr;
  cloud.points.resize(static_cast<std::size_t>(layout.height) * layout.width);
  std::vector<LidarPoint>& points = cloud.points;
  for_each_value(layout, *x, [&](std::size_t i, auto v) { points[i].x = static_cast<float>(v); });
  for_each_value(layout, *y, [&](std::size_t i, auto v) { points[i].y = static_cast<float>(v); });
  for_each_value(layout, *z, [&](std::size_t i, auto v) { points[i].z = static_cast<float>(v); });
  if (intensity != nullptr) {
    for_each_value(layout, *intensity,
                   [&](std::size_t i, auto v) { points[i].intensity = static_cast<float>(v); });
  }
  if (ring != nullptr) {
    std::optional<std::size_t> bad;
    for_each_value(layout, *ring, [&](std::size_t i, auto v) {
      const auto beam = static_cast<double>(v);
      if (beam < 0.0 || beam > std::numeric_limits<std::uint16_t>::max()) {
        if (!bad) bad = i;
        return;
      }
      points[i].ring = static_cast<std::uint16_t>(beam);
    });
    if (bad) {
      throw InputError(source, 0, "fields." + ring->name,
                       fmt::format("point {}: the beam is not a uint16", *bad));
    }
  }
  if (time != nullptr) {
    for_each_value(layout, *time, [&](std::size_t i, auto v) {
      points[i].t = static_cast<float>(static_cast<double>(v) * scale.scale - scale.offset);
    });
  }
  return out;
}

}  // namespace x2car::io
