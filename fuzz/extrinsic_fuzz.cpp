// libFuzzer target for the extrinsic text forms (io/extrinsic_formats.hpp): format detection,
// every form's parser (xyzrpy in degrees and radians, matrix, quaternion, URDF joint, Autoware
// YAML, the reference's), and a round trip: what a numeric form reads, it writes and reads back.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_support.hpp"
#include "x2car/io/autoware_yaml.hpp"
#include "x2car/io/extrinsic_formats.hpp"
#include "x2car/io/urdf_joint.hpp"

namespace {

using namespace x2car;

constexpr io::ExtrinsicFormat kFormats[] = {
    io::ExtrinsicFormat::kXyzRpyDeg, io::ExtrinsicFormat::kXyzRpyRad,
    io::ExtrinsicFormat::kMatrix,    io::ExtrinsicFormat::kQuaternion,
    io::ExtrinsicFormat::kUrdf,      io::ExtrinsicFormat::kAutoware,
    io::ExtrinsicFormat::kReference};

// A parsed extrinsic is finite and its rotation part a rotation.
void check_extrinsic(const Extrinsic& extrinsic, const char* reader) {
  const Eigen::Matrix4d& m = extrinsic.parent_from_child.matrix();
  fuzz::expect_finite_vector(m.reshaped(), reader);
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  if (!(r.transpose() * r).isIdentity(1e-6) || !(std::abs(r.determinant() - 1.0) < 1e-6)) {
    fuzz::finding(std::string(reader) + ": the rotation is not orthonormal");
  }
}

bool is_numeric_form(io::ExtrinsicFormat format) {
  return format != io::ExtrinsicFormat::kUrdf && format != io::ExtrinsicFormat::kAutoware;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = fuzz::as_text(data, size);
  io::detect_extrinsic_format(text);
  io::has_urdf_joint(text);
  io::looks_like_autoware(text);
  for (const io::ExtrinsicFormat format : kFormats) {
    fuzz::accept_input_errors(io::to_string(format), [&] {
      const Extrinsic extrinsic = io::parse_extrinsic(text, format, "fuzz.txt");
      check_extrinsic(extrinsic, io::to_string(format));
      if (!is_numeric_form(format)) return;
      const std::string written = io::format_extrinsic(extrinsic, format);
      try {
        check_extrinsic(io::parse_extrinsic(written, format, "written"), io::to_string(format));
      } catch (const std::exception& error) {
        fuzz::finding(std::string(io::to_string(format)) +
                      ": what it wrote does not read back: " + error.what() + "\n" + written);
      }
    });
  }
  fuzz::accept_input_errors("parse_autoware_all", [&] {
    for (const Extrinsic& extrinsic : io::parse_autoware_all(text, "fuzz.yaml")) {
      check_extrinsic(extrinsic, "parse_autoware_all");
    }
  });
  return 0;
}
