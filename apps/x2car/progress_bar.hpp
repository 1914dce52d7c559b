// A progress bar for long loops, drawn on stderr only when stderr is a terminal, so logs and CI
// output stay clean. Library loops report through a callback of type ProgressCallback and the CLI
// passes ProgressBar::callback().
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <ostream>
#include <string>

namespace x2car::cli {

class ProgressBar {
 public:
  // Draws on std::cerr when it is a terminal, `enabled` and the command's output is not captured
  // (command_output.hpp); otherwise does nothing.
  ProgressBar(std::string label, bool enabled = true);
  // Draws on `stream` unconditionally (for tests and for callers that decided themselves).
  ProgressBar(std::string label, std::ostream& stream);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  // Redraws at most ~10 times a second, and always at the end (done == total).
  void update(std::size_t done, std::size_t total);
  // Ends the line if anything was drawn.
  void finish();

  bool active() const { return stream_ != nullptr; }
  std::function<void(std::size_t, std::size_t)> callback();

 private:
  void draw(std::size_t done, std::size_t total);

  std::string label_;
  std::ostream* stream_ = nullptr;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_draw_{};
};

}  // namespace x2car::cli
