// Shared helpers for line-oriented text files (pose files, extrinsics, CSV layouts): read a file,
// split it into numbered lines and fields, and parse numbers so that every failure is an
// InputError naming the file, the 1-based line and the field.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace x2car::io {

// Reads a whole file. Throws InputError naming the file when it is missing, a directory or
// unreadable.
std::string read_text_file(const std::filesystem::path& path);

// Writes (replaces) a whole file. Throws InputError naming the file when it cannot be written: an
// unwritable output path is a usage error (exit code 2), like a bad input path.
void write_text_file(const std::filesystem::path& path, std::string_view text);

// One line of a text with its 1-based number; `text` views the caller's buffer, without '\r\n'.
struct TextLine {
  std::size_t number = 0;
  std::string_view text;
};

struct LineOptions {
  bool skip_blank = true;     // drop lines that hold only whitespace
  bool skip_comments = true;  // drop lines whose first non-blank character is '#'
};

// Splits a text into lines ('\n' or "\r\n"; a leading UTF-8 byte-order mark is dropped).
std::vector<TextLine> split_lines(std::string_view text, const LineOptions& options = {});

// The 1-based number of the line holding the character at `offset` of `text` (counting '\n'), for
// errors about a position found by searching a whole text.
std::size_t line_number_at(std::string_view text, std::size_t offset);

// Trims spaces, tabs, '\r' and '\n' from both ends.
std::string_view trim(std::string_view text);

// Splits a line into fields. A line holding a comma is split at commas (empty fields are kept, so
// "1,,3" has three fields and a missing value is reported, not skipped); otherwise at runs of
// whitespace. Fields are trimmed.
std::vector<std::string_view> split_fields(std::string_view line);

// Column separators: kAuto is split_fields' rule (commas, else whitespace, which covers tabs); a
// header separated by semicolons (a spreadsheet in a locale with decimal commas) sets the rule for
// its rows.
enum class Delimiter { kAuto, kSemicolon };
// kSemicolon when the header has a ';' and no ',', else kAuto.
Delimiter detect_delimiter(std::string_view header);
// Splits a line at `delimiter` (kAuto: split_fields). Fields are trimmed; empty fields are kept.
std::vector<std::string_view> split_fields(std::string_view line, Delimiter delimiter);
// "comma-separated", "semicolon-separated".
std::string_view delimiter_name(Delimiter delimiter);

// Splits a text into numeric-looking tokens at whitespace, commas, semicolons and brackets
// ([](){}), for matrices pasted from numpy, Eigen or MATLAB. Each token keeps its line number.
struct Token {
  std::size_t line = 0;
  std::string_view text;
};
std::vector<Token> split_number_tokens(std::string_view text);

// Where a value came from, for error messages.
struct FieldLocation {
  std::string file;      // file or source name as the user knows it
  std::size_t line = 0;  // 1-based; 0 = not line-oriented
  std::string field;     // a name ("qx") or a 1-based index ("3")
};

// The name of a field known by its position: "3" for zero-based index 2 (messages count from 1).
std::string field_index(std::size_t zero_based_index);

enum class NonFinite {
  kReject,  // NaN and +-inf are input errors (the default: they must never reach an angle)
  kAllow,   // the format uses them on purpose (e.g. a missing measurement)
};

// Parses a whole field as a double (a leading '+' is accepted). Throws InputError at `where` when
// the field is empty, not a number, has trailing characters, is out of range, or is non-finite
// and `non_finite` is kReject.
double parse_double(std::string_view text, const FieldLocation& where,
                    NonFinite non_finite = NonFinite::kReject);

// Parses a whole field as a signed 64-bit integer; InputError at `where` otherwise.
std::int64_t parse_integer(std::string_view text, const FieldLocation& where);

// Parses a number with no fractional part that fits an int, also when written as a float ("4.0",
// "4e0"): devices write integer codes (solution status, modes) that way. InputError at `where`
// otherwise.
int parse_whole_number(std::string_view text, const FieldLocation& where);

// Splits a line (split_fields) and checks it has exactly `count` fields; otherwise InputError at
// the line: "expected <count> comma-separated fields<count_note>, found <n>", where count_note
// says where the count comes from (e.g. " (as many as the header names)"), or is empty.
std::vector<std::string_view> split_exact_fields(const TextLine& line, std::size_t count,
                                                 const std::string& source,
                                                 std::string_view count_note = {},
                                                 Delimiter delimiter = Delimiter::kAuto);

// Parses the fields of one line as doubles after checking there are exactly `names.size()` of
// them; each error names the field by its name. `file` and `line` locate the line.
std::vector<double> parse_named_doubles(std::span<const std::string_view> fields,
                                        std::span<const char* const> names, const std::string& file,
                                        std::size_t line);

// The shortest text that reads back to the same double ("0.1", "2", "1e-20"; as exact as
// max_digits10 without its trailing noise). -0 is written as 0, which reads back equal.
std::string format_number(double value);
// format_number of each value, joined by `separator`: "1 0 0.5".
std::string format_numbers(std::initializer_list<double> values, std::string_view separator = " ");

// "a, b, c": for messages that list what was expected or found.
std::string join(std::span<const std::string> items, std::string_view separator = ", ");

}  // namespace x2car::io
