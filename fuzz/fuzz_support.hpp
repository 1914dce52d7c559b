// Shared by the libFuzzer targets (fuzz/README.md): what counts as a finding, and scratch files
// for the readers that take a path.
//
// A reader passes an input when it returns or throws x2car::InputError / std::invalid_argument.
// Any other exception, a crash, a leak, undefined behaviour, a hang, or a NaN where the reader
// promises finite numbers is a finding: the target aborts so that libFuzzer saves the input.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

#include "x2car/core/error.hpp"

namespace x2car::fuzz {

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "x2car fuzz finding: %s\n", what.c_str());
  std::abort();
}

// Runs one parse; the input errors a reader is allowed to throw are swallowed (printed when the
// environment sets X2CAR_FUZZ_VERBOSE, to check what a seed reaches), anything else is a finding.
template <typename Parse>
void accept_input_errors(const char* reader, Parse&& parse) {
  static const bool verbose = std::getenv("X2CAR_FUZZ_VERBOSE") != nullptr;
  try {
    parse();
    if (verbose) std::fprintf(stderr, "%s: read\n", reader);
  } catch (const InputError& error) {
    if (verbose) std::fprintf(stderr, "%s: InputError %s\n", reader, error.what());
  } catch (const std::invalid_argument& error) {
    if (verbose) std::fprintf(stderr, "%s: invalid_argument %s\n", reader, error.what());
  } catch (const std::exception& error) {
    finding(std::string(reader) + " threw " + typeid(error).name() + ": " + error.what());
  }
}

// Aborts when `value` is NaN or infinite: `what` names the reader and the field.
inline void expect_finite(double value, const char* what) {
  if (!std::isfinite(value)) finding(std::string(what) + " is not finite");
}

template <typename Vector>
void expect_finite_vector(const Vector& v, const char* what) {
  for (int i = 0; i < static_cast<int>(v.size()); ++i) expect_finite(v[i], what);
}

// A scratch folder unique to this process under the system's temporary folder, created once and
// removed at exit: for the readers that take a path.
inline const std::filesystem::path& scratch_folder() {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("x2car-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(scratch_folder(), ignored);
    });
    return path;
  }();
  return folder;
}

// Writes `bytes` to `path`, replacing what was there.
inline void write_scratch_file(const std::filesystem::path& path, std::string_view bytes) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) finding("cannot write the scratch file " + path.string());
  if (!bytes.empty()) std::fwrite(bytes.data(), 1, bytes.size(), file);
  std::fclose(file);
}

// The input split at lines that hold exactly `separator` (for targets that need several texts,
// such as a folder of files); at most `max_parts` parts, the last one takes the rest.
inline std::vector<std::string_view> split_parts(std::string_view text, std::string_view separator,
                                                 std::size_t max_parts) {
  std::vector<std::string_view> parts;
  const std::string marker = "\n" + std::string(separator) + "\n";
  std::size_t start = 0;
  while (parts.size() + 1 < max_parts) {
    const std::size_t at = text.find(marker, start);
    if (at == std::string_view::npos) break;
    parts.push_back(text.substr(start, at + 1 - start));
    start = at + marker.size();
  }
  parts.push_back(text.substr(start));
  return parts;
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace x2car::fuzz
