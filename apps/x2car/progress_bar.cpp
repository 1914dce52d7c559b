#include "apps/x2car/progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <iostream>

#include "apps/x2car/command_output.hpp"

namespace x2car::cli {
namespace {

constexpr int kBarWidth = 30;
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);

}  // namespace

ProgressBar::ProgressBar(std::string label, bool enabled) : label_(std::move(label)) {
  if (enabled && !command_output_captured() && isatty(STDERR_FILENO) == 1) stream_ = &std::cerr;
}

ProgressBar::ProgressBar(std::string label, std::ostream& stream)
    : label_(std::move(label)), stream_(&stream) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(std::size_t done, std::size_t total) {
  if (stream_ == nullptr || total == 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total && drawn_ && now - last_draw_ < kRedrawInterval) return;
  last_draw_ = now;
  draw(std::min(done, total), total);
}

void ProgressBar::draw(std::size_t done, std::size_t total) {
  const double fraction = static_cast<double>(done) / static_cast<double>(total);
  const int filled = static_cast<int>(fraction * kBarWidth);
  *stream_ << '\r' << label_ << " [" << std::string(static_cast<std::size_t>(filled), '#')
           << std::string(static_cast<std::size_t>(kBarWidth - filled), ' ') << "] " << done << '/'
           << total << std::flush;
  drawn_ = true;
}

void ProgressBar::finish() {
  if (stream_ != nullptr && drawn_) *stream_ << '\n' << std::flush;
  drawn_ = false;
}

std::function<void(std::size_t, std::size_t)> ProgressBar::callback() {
  return [this](std::size_t done, std::size_t total) { update(done, total); };
}

}  // namespace x2car::cli
