#include "apps/x2car/output_paths.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace x2car::cli {
namespace {

namespace fs = std::filesystem;

// The absolute, symlink-free form of a path that may not exist yet.
fs::path resolved(const std::string& path) {
  std::error_code error;
  const fs::path absolute = fs::weakly_canonical(fs::absolute(path), error);
  return error ? fs::absolute(path).lexically_normal() : absolute;
}

// True when `inner` is `outer` or lies below it.
bool is_within(const fs::path& inner, const fs::path& outer) {
  auto outer_part = outer.begin();
  auto inner_part = inner.begin();
  for (; outer_part != outer.end(); ++outer_part, ++inner_part) {
    if (outer_part->empty()) continue;  // the trailing "" of "dir/"
    if (inner_part == inner.end() || *inner_part != *outer_part) return false;
  }
  return true;
}

// Empty when a file can be created in `folder`, else the system's reason. access() alone says
// yes to root on folders no one can write (/proc, a read-only mount seen through a bind), so a
// hidden probe file is created and removed.
std::string why_not_writable(const fs::path& folder) {
  if (access(folder.c_str(), W_OK) != 0) return std::strerror(errno);
  std::string probe = (folder / ".x2car-write-check-XXXXXX").string();
  const int descriptor = mkstemp(probe.data());
  // Where no file can be made (/proc, /sys) the kernel says "No such file or directory" of the
  // new file, which reads as if the folder were missing.
  if (descriptor < 0) {
    return errno == ENOENT ? "no file can be created in it" : std::strerror(errno);
  }
  close(descriptor);
  unlink(probe.c_str());
  return {};
}

// Two names of one file: a hard link has its own path, so only the file system can tell.
bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code error;
  return fs::exists(a, error) && fs::exists(b, error) && fs::equivalent(a, b, error) && !error;
}

void check_not_an_input(const NamedPath& output, const fs::path& output_path,
                        std::span<const NamedPath> inputs) {
  for (const NamedPath& input : inputs) {
    if (input.path.empty()) continue;
    const fs::path input_path = resolved(input.path);
    if (output_path == input_path || same_file(output_path, input_path)) {
      throw std::invalid_argument(fmt::format(
          "{} {} is also the {} file: x2car never writes over the data it reads; choose "
          "another file",
          output.option, output.path, input.option));
    }
    // A new file beside the data is harmless; replacing a file of the data is not.
    std::error_code error;
    if (fs::is_directory(input_path, error) && is_within(output_path, input_path) &&
        fs::exists(output_path, error)) {
      throw std::invalid_argument(fmt::format(
          "{} {} would replace a file of the {} folder {}: x2car never writes over the data it "
          "reads; choose another file",
          output.option, output.path, input.option, input.path));
    }
  }
}

}  // namespace

void check_output_files(std::span<const NamedPath> outputs, std::span<const NamedPath> inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& output = outputs[i];
    if (output.path.empty()) continue;
    const fs::path path = resolved(output.path);
    std::error_code error;
    if (fs::is_directory(path, error)) {
      throw std::invalid_argument(
          fmt::format("{} {} is a folder; give a file name", output.option, output.path));
    }
    const fs::path folder = path.parent_path();
    if (!fs::is_directory(folder, error)) {
      throw std::invalid_argument(fmt::format("{} {}: the folder {} does not exist", output.option,
                                              output.path, folder.string()));
    }
    if (const std::string why = why_not_writable(folder); !why.empty()) {
      throw std::invalid_argument(fmt::format("{} {}: the folder {} is not writable ({})",
                                              output.option, output.path, folder.string(), why));
    }
    if (fs::exists(path, error) && access(path.c_str(), W_OK) != 0) {
      throw std::invalid_argument(fmt::format("{} {}: the file is not writable ({})", output.option,
                                              output.path, std::strerror(errno)));
    }
    check_not_an_input(output, path, inputs);
    for (std::size_t j = 0; j < i; ++j) {
      if (!outputs[j].path.empty() &&
          (resolved(outputs[j].path) == path || same_file(resolved(outputs[j].path), path))) {
        throw std::invalid_argument(fmt::format("{} and {} name the same file {}",
                                                outputs[j].option, output.option, output.path));
      }
    }
  }
}

void check_output_folder(const NamedPath& output, std::span<const NamedPath> inputs) {
  if (output.path.empty()) return;
  const fs::path path = resolved(output.path);
  std::error_code error;
  if (fs::exists(path, error) && !fs::is_directory(path, error)) {
    throw std::invalid_argument(
        fmt::format("{} {} is a file; give a folder", output.option, output.path));
  }
  for (const NamedPath& input : inputs) {
    if (input.path.empty()) continue;
    if (is_within(resolved(input.path), path)) {
      throw std::invalid_argument(fmt::format(
          "{} {} holds the {} input {}: x2car replaces what it writes there, so it never writes "
          "into a folder holding its inputs; choose another folder",
          output.option, output.path, input.option, input.path));
    }
  }
}

}  // namespace x2car::cli
