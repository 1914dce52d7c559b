#include "apps/x2car/command_output.hpp"

#include <iostream>

namespace x2car::cli {
namespace {

// The innermost capture of this thread; null: stdout. Thread-local, as each sensor of `calibrate
// all` runs as one task on one thread from start to end.
thread_local std::ostream* t_captured = nullptr;

}  // namespace

std::ostream& command_output() { return t_captured != nullptr ? *t_captured : std::cout; }

bool command_output_captured() { return t_captured != nullptr; }

CapturedCommandOutput::CapturedCommandOutput(std::ostream& buffer) : previous_(t_captured) {
  t_captured = &buffer;
}

CapturedCommandOutput::~CapturedCommandOutput() { t_captured = previous_; }

}  // namespace x2car::cli
