// ROS 2 messages as CDR bytes (OMG XCDR1, ROS 2's wire and bag encoding "cdr"): a 4-byte
// encapsulation header (0x00 0x01: little-endian; 0x00 0x00: big-endian; then two option bytes),
// then the fields in order, each primitive aligned to its own size (at most 8) counted from the
// end of that header; a string is a uint32 length (with its terminating NUL) and the bytes; a
// sequence a uint32 count and the elements; a fixed array the elements alone.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace x2car::io {

class CdrReader {
 public:
  // Throws InputError naming `source` (e.g. "run.mcap: /odom message 12") when the header is not
  // CDR's.
  CdrReader(std::string_view bytes, std::string source);

  std::int32_t int32(const char* field);
  std::uint32_t uint32(const char* field);
  std::uint8_t uint8(const char* field);
  double float64(const char* field);
  std::string string(const char* field);
  void skip_float64s(std::size_t count, const char* field);  // a fixed float64 array

 private:
  void align(std::size_t size);
  std::string_view take(std::size_t size, const char* field);
  template <typename Unsigned>
  Unsigned read_unsigned(const char* field);

  std::string_view data_;  // after the encapsulation header
  std::string source_;
  std::size_t at_ = 0;
  bool big_endian_ = false;
};

}  // namespace x2car::io
