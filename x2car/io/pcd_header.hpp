// Internal to the PCD reader (pcd.cpp): the parsed header of a PCD file.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace x2car::io::detail {

enum class DataKind { kAscii, kBinary, kBinaryCompressed };

struct PcdField {
  std::string name;
  std::size_t size = 4;    // bytes of one value
  char type = 'F';         // F, U or I
  std::size_t count = 1;   // values per point
  std::size_t offset = 0;  // in a binary point record [bytes]
  std::size_t column = 0;  // first token of the field on an ascii line
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::size_t width = 0, height = 1, points = 0;
  DataKind data = DataKind::kBinary;
  std::size_t point_bytes = 0, tokens = 0;
  std::size_t data_offset = 0;  // first byte after the DATA line
  std::size_t data_line = 0;    // line number of the DATA line
  // Header lines of the keywords, for errors (0 = absent).
  std::size_t fields_line = 0, size_line = 0, type_line = 0, count_line = 0, width_line = 0,
              points_line = 0;
};

// Parses the header up to and including its DATA line; InputError naming the file, the header line
// and the keyword for anything missing or inconsistent.
PcdHeader parse_pcd_header(std::string_view bytes, const std::string& file);

}  // namespace x2car::io::detail
