// Validators for numeric options whose messages stay short: CLI11's own print their range in
// fixed notation (a 309-digit number for "positive").
#pragma once

#include <CLI/CLI.hpp>

namespace x2car::cli {

// A finite number > 0.
CLI::Validator positive_number();
// A finite number >= 0.
CLI::Validator non_negative_number();

}  // namespace x2car::cli
