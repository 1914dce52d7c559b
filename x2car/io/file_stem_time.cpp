#include "x2car/io/file_stem_time.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>

namespace x2car::io {
namespace {

constexpr std::size_t kNanosecondDigits = 16;  // a whole-number stem this long counts nanoseconds

}  // namespace

std::optional<double> time_from_file_stem(std::string_view stem) {
  if (stem.empty() || !std::ranges::all_of(stem, [](char c) {
        return std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '.';
      })) {
    return std::nullopt;
  }
  const auto dots = static_cast<std::size_t>(std::ranges::count(stem, '.'));
  if (dots > 1) return std::nullopt;
  if (dots == 0) {
    if (stem.size() < kNanosecondDigits) return std::nullopt;  // a sequence number, not a time
    std::uint64_t nanoseconds = 0;
    const auto [end, error] = std::from_chars(stem.data(), stem.data() + stem.size(), nanoseconds);
    if (error != std::errc{} || end != stem.data() + stem.size()) return std::nullopt;
    return static_cast<double>(nanoseconds / 1'000'000'000ULL) +
           static_cast<double>(nanoseconds % 1'000'000'000ULL) * 1e-9;
  }
  double seconds = 0.0;
  const auto [end, error] = std::from_chars(stem.data(), stem.data() + stem.size(), seconds);
  if (error != std::errc{} || end != stem.data() + stem.size()) return std::nullopt;
  return seconds;
}

}  // namespace x2car::io
