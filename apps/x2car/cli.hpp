// The x2car command line: global flags, the subcommand table, and the mapping of failures to
// exit codes (exit_codes.hpp).
#pragma once

namespace x2car::cli {

int run_cli(int argc, char** argv);

}  // namespace x2car::cli
