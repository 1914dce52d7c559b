// The bytes of one ROS message, read field by field in either of the two wire encodings bags hold
// (docs/formats.md, "ROS bags"):
//   - ROS 2 CDR (OMG XCDR1, the "cdr" of ROS 2 bags and MCAP): a 4-byte encapsulation header
//     (0x00 0x01: little-endian; 0x00 0x00: big-endian; then two option bytes), then the fields
//     in order, each primitive aligned to its own size (at most 8) counted from the end of that
//     header; a string is a uint32 length counting its terminating NUL, then the bytes; a
//     sequence a uint32 count and the elements; a fixed array the elements alone. A time is
//     int32 sec, uint32 nanosec; std_msgs/Header is stamp, frame_id.
//   - ROS 1 (the "ros1" of ROS 1 bags and MCAP): little-endian, packed without alignment; a
//     string is a uint32 length without a NUL, then the bytes. A time is uint32 sec, uint32 nsec;
//     std_msgs/Header is seq, stamp, frame_id.
// Every read is checked against the message's end; errors are InputErrors naming the source (the
// file and the topic's message) and the field.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace x2car::io {

enum class RosEncoding { kCdr, kRos1 };

struct RosHeader {
  std::int64_t stamp_ns = 0;  // header.stamp as nanoseconds of its clock
  std::string frame_id;
};

// `value` when finite; else an InputError naming `source` and `field` (a message's number that
// x2car would compute with).
double finite_field(double value, const std::string& source, const char* field);

class RosMessageReader {
 public:
  // Throws InputError naming `source` (e.g. "run.mcap (/odom message 12)") when a CDR message's
  // header is not CDR's.
  RosMessageReader(std::string_view bytes, RosEncoding encoding, std::string source);

  std::int32_t int32(const char* field);
  std::uint32_t uint32(const char* field);
  std::uint16_t uint16(const char* field);
  std::uint8_t uint8(const char* field);
  std::uint64_t uint64(const char* field);
  bool boolean(const char* field);
  double float64(const char* field);
  float float32(const char* field);
  std::string string(const char* field);
  // A fixed array of `count` bytes (uint8[N]), a view into the message.
  std::string_view fixed_bytes(std::size_t count, const char* field);
  // A uint8[] sequence: its bytes, a view into the message.
  std::string_view byte_sequence(const char* field);
  void skip_float64s(std::size_t count, const char* field);  // a fixed float64 array
  // builtin_interfaces/Time (CDR) or ROS 1 time, as nanoseconds; `field` names it ("stamp").
  std::int64_t time_ns(const std::string& field);
  // std_msgs/Header in this encoding.
  RosHeader header();

  bool big_endian() const { return big_endian_; }
  const std::string& source() const { return source_; }

 private:
  void align(std::size_t size);
  std::string_view take(std::size_t size, const char* field);
  template <typename Unsigned>
  Unsigned read_unsigned(const char* field);

  std::string_view data_;  // after CDR's encapsulation header
  RosEncoding encoding_;
  std::string source_;
  std::size_t at_ = 0;
  bool big_endian_ = false;
};

}  // namespace x2car::io
