#include "x2car/io/text_lines.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <sstream>
#include <system_error>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

constexpr std::string_view kBlank = " \t\r\n";
constexpr std::string_view kUtf8ByteOrderMark = "\xEF\xBB\xBF";

bool is_blank(std::string_view line) { return line.find_first_not_of(kBlank) == line.npos; }

bool is_comment(std::string_view line) {
  const std::string_view trimmed = trim(line);
  return !trimmed.empty() && trimmed.front() == '#';
}

bool keep_line(std::string_view line, const LineOptions& options) {
  if (options.skip_blank && is_blank(line)) return false;
  if (options.skip_comments && is_comment(line)) return false;
  return true;
}

// Fields are quoted as the user wrote them, shortened so that a binary file gives a short message.
std::string quoted(std::string_view text) {
  constexpr std::size_t kMaxShown = 40;
  if (text.size() <= kMaxShown) return fmt::format("'{}'", text);
  return fmt::format("'{}...'", text.substr(0, kMaxShown));
}

InputError field_error(const FieldLocation& where, const std::string& message) {
  return InputError(where.file, where.line, where.field, message);
}

// from_chars does not accept a leading '+', which people and some tools write.
std::string_view strip_plus(std::string_view text) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '-' && text[1] != '+') {
    return text.substr(1);
  }
  return text;
}

bool is_token_separator(char c) {
  return std::string_view(" \t\r\n,;[](){}").find(c) != std::string_view::npos;
}

}  // namespace

std::string read_text_file(const std::filesystem::path& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError(path.string(), "is a directory, expected a file");
  }
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(path.string(), "cannot open file for reading");
  std::ostringstream contents;
  contents << stream.rdbuf();
  if (stream.bad()) throw InputError(path.string(), "read error");
  return std::move(contents).str();
}

void write_text_file(const std::filesystem::path& path, std::string_view text) {
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  if (!stream) throw InputError(path.string(), "cannot open file for writing");
  stream.write(text.data(), static_cast<std::streamsize>(text.size()));
  stream.close();
  if (!stream) throw InputError(path.string(), "write error");
}

std::vector<TextLine> split_lines(std::string_view text, const LineOptions& options) {
  if (text.starts_with(kUtf8ByteOrderMark)) text.remove_prefix(kUtf8ByteOrderMark.size());
  std::vector<TextLine> lines;
  std::size_t number = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    std::string_view line = text.substr(0, end);
    text.remove_prefix(end == text.npos ? text.size() : end + 1);
    if (line.ends_with('\r')) line.remove_suffix(1);
    ++number;
    if (keep_line(line, options)) lines.push_back({number, line});
  }
  return lines;
}

std::size_t line_number_at(std::string_view text, std::size_t offset) {
  const std::string_view before = text.substr(0, offset);
  return 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
}

std::string_view trim(std::string_view text) {
  const std::size_t begin = text.find_first_not_of(kBlank);
  if (begin == text.npos) return {};
  const std::size_t end = text.find_last_not_of(kBlank);
  return text.substr(begin, end - begin + 1);
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  if (line.find(',') != line.npos) {
    std::size_t begin = 0;
    for (std::size_t comma = line.find(','); comma != line.npos; comma = line.find(',', begin)) {
      fields.push_back(trim(line.substr(begin, comma - begin)));
      begin = comma + 1;
    }
    fields.push_back(trim(line.substr(begin)));
    return fields;
  }
  for (std::size_t begin = line.find_first_not_of(kBlank); begin != line.npos;) {
    const std::size_t end = line.find_first_of(kBlank, begin);
    fields.push_back(line.substr(begin, end - begin));
    begin = line.find_first_not_of(kBlank, end);
  }
  return fields;
}

Delimiter detect_delimiter(std::string_view header) {
  if (header.find(',') != header.npos) return Delimiter::kAuto;
  if (header.find(';') != header.npos) return Delimiter::kSemicolon;
  return Delimiter::kAuto;
}

std::vector<std::string_view> split_fields(std::string_view line, Delimiter delimiter) {
  if (delimiter == Delimiter::kAuto) return split_fields(line);
  const char separator = ';';
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  for (std::size_t end = line.find(separator); end != line.npos;
       end = line.find(separator, begin)) {
    fields.push_back(trim(line.substr(begin, end - begin)));
    begin = end + 1;
  }
  fields.push_back(trim(line.substr(begin)));
  return fields;
}

std::string_view delimiter_name(Delimiter delimiter) {
  switch (delimiter) {
    case Delimiter::kSemicolon:
      return "semicolon-separated";
    case Delimiter::kAuto:
      break;
  }
  return "comma-separated";
}

std::vector<Token> split_number_tokens(std::string_view text) {
  std::vector<Token> tokens;
  std::size_t line = 1;
  std::size_t begin = text.npos;
  for (std::size_t i = 0; i <= text.size(); ++i) {
    const bool separator = i == text.size() || is_token_separator(text[i]);
    if (!separator && begin == text.npos) begin = i;
    if (separator && begin != text.npos) {
      tokens.push_back({line, text.substr(begin, i - begin)});
      begin = text.npos;
    }
    if (i < text.size() && text[i] == '\n') ++line;
  }
  return tokens;
}

std::string field_index(std::size_t zero_based_index) {
  return std::to_string(zero_based_index + 1);
}

double parse_double(std::string_view text, const FieldLocation& where, NonFinite non_finite) {
  if (text.empty()) throw field_error(where, "empty field, expected a number");
  const std::string_view digits = strip_plus(text);
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc::result_out_of_range) {
    throw field_error(where, fmt::format("number {} is out of range", quoted(text)));
  }
  if (error != std::errc() || end != digits.data() + digits.size()) {
    throw field_error(where, fmt::format("not a number: {}", quoted(text)));
  }
  if (non_finite == NonFinite::kReject && !std::isfinite(value)) {
    // Said without echoing "nan": a NaN in a message reads as a computation gone wrong.
    throw field_error(where, std::isnan(value)
                                 ? std::string("not-a-number value; expected a finite number")
                                 : fmt::format("{} is not a finite number", quoted(text)));
  }
  return value;
}

std::int64_t parse_integer(std::string_view text, const FieldLocation& where) {
  if (text.empty()) throw field_error(where, "empty field, expected an integer");
  const std::string_view digits = strip_plus(text);
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc::result_out_of_range) {
    throw field_error(where, fmt::format("integer {} is out of range", quoted(text)));
  }
  if (error != std::errc() || end != digits.data() + digits.size()) {
    throw field_error(where, fmt::format("not an integer: {}", quoted(text)));
  }
  return value;
}

int parse_whole_number(std::string_view text, const FieldLocation& where) {
  const double value = parse_double(text, where);
  if (value != std::floor(value) || value < INT_MIN || value > INT_MAX) {
    throw field_error(where, fmt::format("expected an integer, found '{}'", text));
  }
  return static_cast<int>(value);
}

std::vector<std::string_view> split_exact_fields(const TextLine& line, std::size_t count,
                                                 const std::string& source,
                                                 std::string_view count_note, Delimiter delimiter) {
  std::vector<std::string_view> fields = split_fields(line.text, delimiter);
  if (fields.size() != count) {
    throw InputError(source, line.number, {},
                     fmt::format("expected {} {} fields{}, found {}", count,
                                 delimiter_name(delimiter), count_note, fields.size()));
  }
  return fields;
}

std::vector<double> parse_named_doubles(std::span<const std::string_view> fields,
                                        std::span<const char* const> names, const std::string& file,
                                        std::size_t line) {
  if (fields.size() != names.size()) {
    const std::vector<std::string> expected(names.begin(), names.end());
    throw InputError(file, line, {},
                     fmt::format("expected {} fields ({}), found {}", names.size(),
                                 join(expected, " "), fields.size()));
  }
  std::vector<double> values(fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    values[i] = parse_double(fields[i], {file, line, names[i]});
  }
  return values;
}

std::string format_number(double value) { return fmt::format("{}", value == 0.0 ? 0.0 : value); }

std::string format_numbers(std::initializer_list<double> values, std::string_view separator) {
  std::string text;
  for (const double value : values) {
    if (!text.empty()) text += separator;
    text += format_number(value);
  }
  return text;
}

std::string join(std::span<const std::string> items, std::string_view separator) {
  std::string joined;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) joined += separator;
    joined += items[i];
  }
  return joined;
}

}  // namespace x2car::io
