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
  // ROS 2's "<sec>_<nanosec>".
  if (const std::size_t underscore = stem.find('_'); underscore != std::string_view::npos) {
    const std::string_view seconds_text = stem.substr(0, underscore);
    const std::string_view nanoseconds_text = stem.substr(underscore + 1);
    const auto digits = [](std::string_view text) {
      return !text.empty() && std::ranges::all_of(text, [](char c) {
        return std::isdigit(static_cast<unsigned char>(c)) != 0;
      });
    };
    if (!digits(seconds_text) || !digits(nanoseconds_text) || nanoseconds_text.size() > 9) {
      return std::nullopt;
    }
    std::uint64_t seconds = 0;
    std::uint64_t nanoseconds = 0;
    const char* seconds_end = seconds_text.data() + seconds_text.size();
    const char* nanoseconds_end = nanoseconds_text.data() + nanoseconds_text.size();
    if (std::from_chars(seconds_text.data(), seconds_end, seconds).ptr != seconds_end ||
        std::from_chars(nanoseconds_text.data(), nanoseconds_end, nanoseconds).ptr !=
            nanoseconds_end) {
      return std::nullopt;
    }
    return static_cast<double>(seconds) + static_cast<double>(nanoseconds) * 1e-9;
  }
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
