#include "x2car/io/ros_message.hpp"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <utility>

#include "x2car/core/error.hpp"

namespace x2car::io {

RosMessageReader::RosMessageReader(std::string_view bytes, RosEncoding encoding, std::string source)
    : data_(bytes), encoding_(encoding), source_(std::move(source)) {
  if (encoding_ == RosEncoding::kRos1) return;
  if (bytes.size() < 4 || bytes[0] != 0 || (bytes[1] != 0 && bytes[1] != 1)) {
    throw InputError(source_, "not a CDR message (its first bytes are not 00 00 or 00 01)");
  }
  big_endian_ = bytes[1] == 0;
  data_ = bytes.substr(4);
}

void RosMessageReader::align(std::size_t size) {
  if (encoding_ == RosEncoding::kRos1) return;  // ROS 1 packs its fields
  const std::size_t aligned = (at_ + size - 1) / size * size;
  at_ = std::min(aligned, data_.size() + 1);  // past the end: the next take reports it
}

std::string_view RosMessageReader::take(std::size_t size, const char* field) {
  if (at_ > data_.size() || size > data_.size() - at_) {
    throw InputError(source_, 0, field,
                     fmt::format("the message ends inside this field ({} bytes)", data_.size()));
  }
  const std::string_view part = data_.substr(at_, size);
  at_ += size;
  return part;
}

template <typename Unsigned>
Unsigned RosMessageReader::read_unsigned(const char* field) {
  align(sizeof(Unsigned));
  const std::string_view bytes = take(sizeof(Unsigned), field);
  Unsigned value = 0;
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) {
    const auto byte = static_cast<Unsigned>(static_cast<unsigned char>(bytes[i]));
    value |= big_endian_ ? byte << (8 * (sizeof(Unsigned) - 1 - i)) : byte << (8 * i);
  }
  return value;
}

std::int32_t RosMessageReader::int32(const char* field) {
  return std::bit_cast<std::int32_t>(read_unsigned<std::uint32_t>(field));
}

std::uint32_t RosMessageReader::uint32(const char* field) {
  return read_unsigned<std::uint32_t>(field);
}

std::uint16_t RosMessageReader::uint16(const char* field) {
  return read_unsigned<std::uint16_t>(field);
}

std::uint8_t RosMessageReader::uint8(const char* field) {
  return read_unsigned<std::uint8_t>(field);
}

std::uint64_t RosMessageReader::uint64(const char* field) {
  return read_unsigned<std::uint64_t>(field);
}

bool RosMessageReader::boolean(const char* field) { return uint8(field) != 0; }

double RosMessageReader::float64(const char* field) {
  return std::bit_cast<double>(read_unsigned<std::uint64_t>(field));
}

float RosMessageReader::float32(const char* field) {
  return std::bit_cast<float>(read_unsigned<std::uint32_t>(field));
}

std::string_view RosMessageReader::fixed_bytes(std::size_t count, const char* field) {
  return take(count, field);
}

std::string RosMessageReader::string(const char* field) {
  const std::uint32_t length = uint32(field);
  const std::string_view bytes = take(length, field);
  if (encoding_ == RosEncoding::kRos1) return std::string(bytes);
  // CDR's length counts the terminating NUL.
  return std::string(bytes.substr(0, bytes.empty() ? 0 : bytes.size() - 1));
}

std::string_view RosMessageReader::byte_sequence(const char* field) {
  const std::uint32_t count = uint32(field);
  return take(count, field);
}

void RosMessageReader::skip_float64s(std::size_t count, const char* field) {
  align(8);
  take(8 * count, field);
}

std::int64_t RosMessageReader::time_ns(const std::string& field) {
  const std::string sec_field = field + ".sec";
  const std::string nanosec_field =
      field + (encoding_ == RosEncoding::kRos1 ? ".nsec" : ".nanosec");
  // ROS 1 counts unsigned seconds, ROS 2 signed.
  const std::int64_t sec = encoding_ == RosEncoding::kRos1
                               ? static_cast<std::int64_t>(uint32(sec_field.c_str()))
                               : static_cast<std::int64_t>(int32(sec_field.c_str()));
  const std::uint32_t nanosec = uint32(nanosec_field.c_str());
  if (nanosec >= 1'000'000'000U) {
    throw InputError(source_, 0, nanosec_field, fmt::format("{} is not below 10^9", nanosec));
  }
  return sec * 1'000'000'000LL + nanosec;
}

RosHeader RosMessageReader::header() {
  if (encoding_ == RosEncoding::kRos1) uint32("header.seq");
  RosHeader header;
  header.stamp_ns = time_ns("header.stamp");
  header.frame_id = string("header.frame_id");
  return header;
}

double finite_field(double value, const std::string& source, const char* field) {
  if (!std::isfinite(value)) throw InputError(source, 0, field, "not a finite number");
  return value;
}

}  // namespace x2car::io
