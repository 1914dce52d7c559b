// Output paths are checked before any work is done, so that a long run never ends in "cannot
// write" and never overwrites the data it read.
#pragma once

#include <span>
#include <string>

namespace x2car::cli {

// A path given on the command line and the option that gave it, for the messages.
struct NamedPath {
  std::string option;  // e.g. "--out"
  std::string path;    // empty: not given
};

// Throws std::invalid_argument (exit 2) when an output file is a folder, its folder does not
// exist or cannot be written, two outputs are the same file, or an output is an input or would
// replace a file inside an input folder.
void check_output_files(std::span<const NamedPath> outputs, std::span<const NamedPath> inputs);

// For an output folder that will be filled with files (simulate --out): refused when it is an
// existing file or one of the inputs lies inside it or is it.
void check_output_folder(const NamedPath& output, std::span<const NamedPath> inputs);

}  // namespace x2car::cli
