// One name table per enum drives parsing, printing and the CLI's choices (issue 11, item 4).
// Each enum keeps one constexpr table beside its functions:
//
//   constexpr std::array<EnumName<YawMethod>, 3> kYawMethodNames{{
//       {YawMethod::kAuto, "auto"}, {YawMethod::kTrackHeading, "track_heading"}, ...}};
//
// and its to_string, ..._from_string and ..._names() (the list the CLI offers) are one line each
// over the helpers below.
#pragma once

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace x2car {

template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;  // a string literal: usable as const char*, std::string or std::string_view
};

namespace detail {
// Throws std::invalid_argument "unknown <what> '<text>'; the valid names are: <valid>".
[[noreturn]] void throw_unknown_name(std::string_view what, std::string_view text,
                                     const std::vector<std::string>& valid);
}  // namespace detail

// The name of `value`; throws std::logic_error for a value missing from the table (a bug).
template <typename Enum, std::size_t N>
const char* enum_to_string(const std::array<EnumName<Enum>, N>& table, Enum value) {
  for (const EnumName<Enum>& entry : table) {
    if (entry.value == value) return entry.name;
  }
  throw std::logic_error("enum value missing from its name table");
}

// The names in table order, e.g. for CLI::IsMember and for messages.
template <typename Enum, std::size_t N>
std::vector<std::string> enum_names(const std::array<EnumName<Enum>, N>& table) {
  std::vector<std::string> names;
  names.reserve(N);
  for (const EnumName<Enum>& entry : table) names.emplace_back(entry.name);
  return names;
}

// The value named `text` (exact, case-sensitive); throws std::invalid_argument "unknown <what>
// '<text>'; the valid names are: a, b, c" otherwise. `what` names the kind, e.g. "yaw method".
template <typename Enum, std::size_t N>
Enum enum_from_string(const std::array<EnumName<Enum>, N>& table, std::string_view text,
                      std::string_view what) {
  for (const EnumName<Enum>& entry : table) {
    if (text == entry.name) return entry.value;
  }
  detail::throw_unknown_name(what, text, enum_names(table));
}

}  // namespace x2car
