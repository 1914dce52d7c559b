#include "x2car/io/pcd_header.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <limits>
#include <optional>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io::detail {
namespace {

// The largest point record accepted [bytes]: far beyond any LiDAR's (PCL's own are below 100), and
// small enough that no product of it with a point count read from the file can overflow unnoticed.
constexpr std::size_t kMaxPointBytes = std::size_t{1} << 20;

class HeaderParser {
 public:
  HeaderParser(std::string_view bytes, const std::string& file) : bytes_(bytes), file_(file) {}

  PcdHeader parse() {
    std::optional<std::size_t> size_count, type_count;
    std::vector<std::size_t> counts;
    std::optional<std::size_t> points;
    std::size_t pos = 0;
    while (pos < bytes_.size()) {
      const std::size_t end = std::min(bytes_.find('\n', pos), bytes_.size());
      const std::string_view line = trim(bytes_.substr(pos, end - pos));
      pos = end + 1;
      ++line_;
      if (line.empty() || line.front() == '#') continue;
      std::vector<std::string_view> words = split_fields(line);
      const std::string_view key = words.front();
      words.erase(words.begin());
      if (key == "VERSION" || key == "VIEWPOINT") continue;
      if (key == "FIELDS" || key == "COLUMNS") {
        header_.fields_line = line_;
        for (const auto word : words) header_.fields.push_back({std::string(word)});
      } else if (key == "SIZE") {
        require_fields("SIZE");
        header_.size_line = line_;
        size_count = words.size();
        for (std::size_t i = 0; i < words.size() && i < header_.fields.size(); ++i)
          header_.fields[i].size = number(words[i], "SIZE");
      } else if (key == "TYPE") {
        require_fields("TYPE");
        header_.type_line = line_;
        type_count = words.size();
        for (std::size_t i = 0; i < words.size() && i < header_.fields.size(); ++i) {
          if (words[i].size() != 1) fail("TYPE", "type '{}' is not one letter", words[i]);
          header_.fields[i].type = words[i].front();
        }
      } else if (key == "COUNT") {
        require_fields("COUNT");
        header_.count_line = line_;
        for (const auto word : words) counts.push_back(number(word, "COUNT"));
      } else if (key == "WIDTH") {
        header_.width_line = line_;
        header_.width = single_number(words, "WIDTH");
      } else if (key == "HEIGHT") {
        header_.height = single_number(words, "HEIGHT");
      } else if (key == "POINTS") {
        header_.points_line = line_;
        points = single_number(words, "POINTS");
      } else if (key == "DATA") {
        header_.data_line = line_;
        header_.data_offset = std::min(pos, bytes_.size());
        header_.data = data_kind(words);
        check(size_count, type_count, counts, points);
        return header_;
      } else {
        fail("", "unknown header keyword '{}'", key);
      }
    }
    throw InputError(file_, "the header has no DATA line (the file is empty or truncated)");
  }

 private:
  template <typename... Args>
  [[noreturn]] void fail_at(std::size_t line, std::string field, fmt::format_string<Args...> text,
                            Args&&... args) const {
    throw InputError(file_, line, std::move(field), fmt::format(text, std::forward<Args>(args)...));
  }
  template <typename... Args>
  [[noreturn]] void fail(std::string field, fmt::format_string<Args...> text,
                         Args&&... args) const {
    fail_at(line_, std::move(field), text, std::forward<Args>(args)...);
  }

  void require_fields(const char* key) const {
    if (header_.fields_line == 0) fail(key, "{} comes before FIELDS", key);
  }

  std::size_t number(std::string_view word, const char* key) const {
    std::size_t value = 0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (error != std::errc() || end != word.data() + word.size()) {
      fail(key, "'{}' is not a non-negative integer", word);
    }
    return value;
  }

  std::size_t single_number(const std::vector<std::string_view>& words, const char* key) const {
    if (words.size() != 1) fail(key, "expected one number, found {}", words.size());
    return number(words.front(), key);
  }

  DataKind data_kind(const std::vector<std::string_view>& words) const {
    if (words.size() == 1 && words.front() == "ascii") return DataKind::kAscii;
    if (words.size() == 1 && words.front() == "binary") return DataKind::kBinary;
    if (words.size() == 1 && words.front() == "binary_compressed")
      return DataKind::kBinaryCompressed;
    fail("DATA", "expected ascii, binary or binary_compressed");
  }

  void check(std::optional<std::size_t> size_count, std::optional<std::size_t> type_count,
             const std::vector<std::size_t>& counts, std::optional<std::size_t> points) {
    auto& fields = header_.fields;
    if (header_.fields_line == 0)
      fail_at(header_.data_line, "FIELDS", "no FIELDS line before DATA");
    if (!size_count || *size_count != fields.size()) {
      fail_at(header_.size_line, "SIZE", "{} sizes for {} fields", size_count.value_or(0),
              fields.size());
    }
    if (!type_count || *type_count != fields.size()) {
      fail_at(header_.type_line, "TYPE", "{} types for {} fields", type_count.value_or(0),
              fields.size());
    }
    if (header_.count_line != 0 && counts.size() != fields.size()) {
      fail_at(header_.count_line, "COUNT", "{} counts for {} fields", counts.size(), fields.size());
    }
    for (std::size_t i = 0; i < fields.size(); ++i) {
      PcdField& field = fields[i];
      if (!counts.empty()) field.count = counts[i];
      check_type(field);
      if (field.count == 0)
        fail_at(header_.count_line, "COUNT", "field '{}' has COUNT 0", field.name);
      // A corrupt COUNT must not wrap the record size around (the size then drives allocations).
      if (field.count > (kMaxPointBytes - header_.point_bytes) / field.size) {
        fail_at(header_.count_line, "COUNT",
                "field '{}' with COUNT {} makes a point record larger than {} bytes", field.name,
                field.count, kMaxPointBytes);
      }
      field.offset = header_.point_bytes;
      field.column = header_.tokens;
      header_.point_bytes += field.size * field.count;
      header_.tokens += field.count;
    }
    if (header_.width_line == 0) fail_at(header_.data_line, "WIDTH", "no WIDTH line before DATA");
    if (header_.height != 0 &&
        header_.width > std::numeric_limits<std::size_t>::max() / header_.height) {
      fail_at(header_.width_line, "WIDTH", "WIDTH x HEIGHT = {} x {} is too large", header_.width,
              header_.height);
    }
    header_.points = header_.width * header_.height;
    if (points && *points != header_.points) {
      fail_at(header_.points_line, "POINTS", "POINTS {} but WIDTH x HEIGHT = {} x {}", *points,
              header_.width, header_.height);
    }
  }

  void check_type(const PcdField& field) const {
    const std::size_t s = field.size;
    const bool valid_size = s == 1 || s == 2 || s == 4 || s == 8;
    if (field.type != 'F' && field.type != 'U' && field.type != 'I') {
      fail_at(header_.type_line, "TYPE", "unknown type '{}' of field '{}' (expected F, U or I)",
              field.type, field.name);
    }
    if (!valid_size || (field.type == 'F' && s != 4 && s != 8)) {
      fail_at(header_.size_line, "SIZE", "size {} is not valid for type {} of field '{}'", s,
              field.type, field.name);
    }
  }

  std::string_view bytes_;
  const std::string& file_;
  std::size_t line_ = 0;
  PcdHeader header_;
};

}  // namespace

PcdHeader parse_pcd_header(std::string_view bytes, const std::string& file) {
  return HeaderParser(bytes, file).parse();
}

}  // namespace x2car::io::detail
