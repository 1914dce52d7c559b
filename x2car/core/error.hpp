// Typed failures. Bad input is an InputError naming the file and, where known, the line and field;
// the CLI turns it into exit code 2. Too little usable data is not an error but a
// CalibrationResult with status insufficient_data (exit code 1).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace x2car {

class InputError : public std::runtime_error {
 public:
  // `line` is 1-based; 0 means the message is about the whole file. `field` may be empty.
  InputError(std::string file, std::size_t line, std::string field, const std::string& message);
  InputError(std::string file, const std::string& message)
      : InputError(std::move(file), 0, {}, message) {}

  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }
  const std::string& field() const { return field_; }

 private:
  std::string file_;
  std::size_t line_ = 0;
  std::string field_;
};

}  // namespace x2car
