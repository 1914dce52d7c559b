#include "x2car/io/jpeg_data.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace x2car::io {

namespace {

constexpr unsigned char kMarkerPrefix = 0xFF;
constexpr unsigned char kStartOfImage = 0xD8;
constexpr unsigned char kEndOfImage = 0xD9;
constexpr unsigned char kStartOfScan = 0xDA;
constexpr unsigned char kTemporary = 0x01;  // TEM: no length

bool is_restart(unsigned char marker) { return marker >= 0xD0 && marker <= 0xD7; }

}  // namespace

bool starts_as_jpeg(std::span<const unsigned char> data) {
  return data.size() >= 2 && data[0] == kMarkerPrefix && data[1] == kStartOfImage;
}

std::optional<std::size_t> jpeg_break_offset(std::span<const unsigned char> data) {
  if (!starts_as_jpeg(data)) return 0;
  const std::size_t size = data.size();
  std::size_t pos = 2;
  while (true) {
    if (pos >= size) return size;
    if (data[pos] != kMarkerPrefix) return pos;              // where a marker must start
    while (pos < size && data[pos] == kMarkerPrefix) ++pos;  // fill bytes
    if (pos >= size) return size;
    const unsigned char marker = data[pos++];
    if (marker == kEndOfImage) return std::nullopt;
    if (is_restart(marker) || marker == kTemporary) continue;
    if (marker == 0x00 || marker == kStartOfImage) return pos - 2;
    if (pos + 2 > size) return size;
    const std::size_t length = (std::size_t{data[pos]} << 8) | data[pos + 1];
    if (length < 2) return pos;
    if (pos + length > size) return size;
    pos += length;
    if (marker != kStartOfScan) continue;
    // The scan's entropy-coded data, up to the next marker.
    while (true) {
      const auto found =
          std::find(data.begin() + static_cast<std::ptrdiff_t>(pos), data.end(), kMarkerPrefix);
      pos = static_cast<std::size_t>(found - data.begin());
      if (pos + 1 >= size) return size;
      const unsigned char next = data[pos + 1];
      if (next != 0x00 && !is_restart(next)) break;  // a marker: the loop above reads it
      pos += 2;
    }
  }
}

std::string describe_jpeg_break(std::size_t offset, std::size_t size) {
  if (offset >= size) {
    return fmt::format(
        "a JPEG cut short: its data ends after {} bytes, before its end-of-image marker", size);
  }
  return fmt::format("a JPEG cut short: its markers break off at byte {} of {}", offset, size);
}

std::optional<std::string> jpeg_cut_short(std::span<const unsigned char> data) {
  if (!starts_as_jpeg(data)) return std::nullopt;
  const std::optional<std::size_t> offset = jpeg_break_offset(data);
  if (!offset) return std::nullopt;
  return describe_jpeg_break(*offset, data.size());
}

}  // namespace x2car::io
