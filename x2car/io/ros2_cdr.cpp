#include "x2car/io/ros2_cdr.hpp"

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <utility>

#include "x2car/core/error.hpp"

namespace x2car::io {

CdrReader::CdrReader(std::string_view bytes, std::string source) : source_(std::move(source)) {
  if (bytes.size() < 4 || bytes[0] != 0 || (bytes[1] != 0 && bytes[1] != 1)) {
    throw InputError(source_, "not a CDR message (its first bytes are not 00 00 or 00 01)");
  }
  big_endian_ = bytes[1] == 0;
  data_ = bytes.substr(4);
}

void CdrReader::align(std::size_t size) {
  const std::size_t aligned = (at_ + size - 1) / size * size;
  at_ = std::min(aligned, data_.size() + 1);  // past the end: the next take reports it
}

std::string_view CdrReader::take(std::size_t size, const char* field) {
  if (at_ > data_.size() || size > data_.size() - at_) {
    throw InputError(source_, 0, field,
                     fmt::format("the message ends inside this field ({} bytes)", data_.size()));
  }
  const std::string_view part = data_.substr(at_, size);
  at_ += size;
  return part;
}

template <typename Unsigned>
Unsigned CdrReader::read_unsigned(const char* field) {
  align(sizeof(Unsigned));
  const std::string_view bytes = take(sizeof(Unsigned), field);
  Unsigned value = 0;
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) {
    const auto byte = static_cast<Unsigned>(static_cast<unsigned char>(bytes[i]));
    value |= big_endian_ ? byte << (8 * (sizeof(Unsigned) - 1 - i)) : byte << (8 * i);
  }
  return value;
}

std::int32_t CdrReader::int32(const char* field) {
  return std::bit_cast<std::int32_t>(read_unsigned<std::uint32_t>(field));
}

std::uint32_t CdrReader::uint32(const char* field) { return read_unsigned<std::uint32_t>(field); }

std::uint8_t CdrReader::uint8(const char* field) { return read_unsigned<std::uint8_t>(field); }

double CdrReader::float64(const char* field) {
  return std::bit_cast<double>(read_unsigned<std::uint64_t>(field));
}

std::string CdrReader::string(const char* field) {
  const std::uint32_t length = uint32(field);
  const std::string_view bytes = take(length, field);
  // The length counts the terminating NUL.
  return std::string(bytes.substr(0, bytes.empty() ? 0 : bytes.size() - 1));
}

void CdrReader::skip_float64s(std::size_t count, const char* field) {
  align(8);
  take(8 * count, field);
}

}  // namespace x2car::io
