// The unit of angles in a file: GNSS/INS columns, radar azimuths, extrinsic text forms.
#pragma once

namespace x2car::io {

enum class AngleUnit { kRadians, kDegrees };

}  // namespace x2car::io
