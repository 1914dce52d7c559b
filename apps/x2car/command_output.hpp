// Where a command's report for a person goes: stdout, or, while `calibrate all` runs its sensors
// side by side, a buffer of the task running the sensor, printed in the sensors' order when all
// have finished (so that their summaries do not interleave). A capture holds on the thread that
// made it until it ends; captures nest (one task may run another's on its thread while waiting).
#pragma once

#include <ostream>

namespace x2car::cli {

// stdout, or the innermost capture on this thread.
std::ostream& command_output();

// True while a capture holds on this thread: progress bars stay off (several would share a line).
bool command_output_captured();

class CapturedCommandOutput {
 public:
  explicit CapturedCommandOutput(std::ostream& buffer);
  ~CapturedCommandOutput();
  CapturedCommandOutput(const CapturedCommandOutput&) = delete;
  CapturedCommandOutput& operator=(const CapturedCommandOutput&) = delete;

 private:
  std::ostream* previous_;
};

}  // namespace x2car::cli
