#include "x2car/core/options_check.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

const char* opening(Bounds bounds) {
  return bounds == Bounds::kOpen || bounds == Bounds::kOpenMin ? "(" : "[";
}

const char* closing(Bounds bounds) {
  return bounds == Bounds::kOpen || bounds == Bounds::kOpenMax ? ")" : "]";
}

bool inside(double value, double min, double max, Bounds bounds) {
  const bool above_min =
      bounds == Bounds::kOpen || bounds == Bounds::kOpenMin ? value > min : value >= min;
  const bool below_max =
      bounds == Bounds::kOpen || bounds == Bounds::kOpenMax ? value < max : value <= max;
  return above_min && below_max;
}

}  // namespace

std::string OptionsCheck::name(std::string_view field) const {
  return fmt::format("{}.{}", options_name_, field);
}

void OptionsCheck::fail(std::string_view field, std::string_view requirement, double value) const {
  throw std::invalid_argument(fmt::format("{} {} (got {:g})", name(field), requirement, value));
}

void OptionsCheck::finite(std::string_view field, double value) const {
  if (!std::isfinite(value)) fail(field, "must be finite", value);
}

void OptionsCheck::positive(std::string_view field, double value) const {
  if (!(value > 0.0 && std::isfinite(value))) fail(field, "must be > 0 and finite", value);
}

void OptionsCheck::non_negative(std::string_view field, double value) const {
  if (!(value >= 0.0 && std::isfinite(value))) fail(field, "must be >= 0 and finite", value);
}

void OptionsCheck::non_negative(std::string_view field, const EulerAngles& angles) const {
  non_negative(fmt::format("{}.roll", field), angles.roll);
  non_negative(fmt::format("{}.pitch", field), angles.pitch);
  non_negative(fmt::format("{}.yaw", field), angles.yaw);
}

void OptionsCheck::at_least(std::string_view field, double value, double min) const {
  if (!(value >= min)) fail(field, fmt::format("must be >= {:g}", min), value);
}

void OptionsCheck::at_most(std::string_view field, double value, double max) const {
  if (!(value <= max)) fail(field, fmt::format("must be <= {:g}", max), value);
}

void OptionsCheck::in_range(std::string_view field, double value, double min, double max,
                            Bounds bounds) const {
  if (!inside(value, min, max, bounds)) {
    fail(field,
         fmt::format("must be in {}{:g}, {:g}{}", opening(bounds), min, max, closing(bounds)),
         value);
  }
}

void OptionsCheck::ordered(std::string_view min_field, double min, std::string_view max_field,
                           double max) const {
  finite(min_field, min);
  finite(max_field, max);
  if (!(min <= max)) {
    throw std::invalid_argument(fmt::format("{} must be <= {} (got {:g} > {:g})", name(min_field),
                                            name(max_field), min, max));
  }
}

void OptionsCheck::that(bool condition, std::string_view field, std::string_view requirement,
                        double value) const {
  if (!condition) fail(field, requirement, value);
}

void OptionsCheck::that(bool condition, std::string_view field,
                        std::string_view requirement) const {
  if (!condition) throw std::invalid_argument(fmt::format("{} {}", name(field), requirement));
}

}  // namespace x2car
