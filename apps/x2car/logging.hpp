// One logger for the whole CLI, on stderr; the library never prints.
#pragma once

namespace x2car::cli {

// verbosity: -1 quiet (warnings and errors), 0 normal, 1 debug, 2 and more trace.
void configure_logging(int verbosity);

}  // namespace x2car::cli
