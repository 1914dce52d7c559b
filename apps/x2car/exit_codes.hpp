// The process exit codes of the x2car CLI (DESIGN §6).
#pragma once

namespace x2car::cli {

enum ExitCode : int {
  kExitOk = 0,  // a result was produced
  // The input was read but holds too little usable data, or the fit failed its own checks
  // (status insufficient_data or unreliable); the reason is printed.
  kExitInsufficientData = 1,
  kExitUsageOrInputError = 2,  // bad arguments, or a file that cannot be read or parsed
  kExitInternalError = 3,      // a bug in x2car: an error no input should cause
};

}  // namespace x2car::cli
