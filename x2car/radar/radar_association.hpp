// Association of radar detections into tracks, for radars that report clusters without track ids
// (many real exports), so that the position method (radar_position_method.hpp; paper §III-D) can
// group them into objects as it groups a tracking radar's ids.
//
// Global nearest neighbour, scan by scan, with a constant-velocity gate in a frame that does not
// turn with the car. The radar's mounting yaw psi is what is being calibrated, so a detection
// cannot be put into the vehicle frame; but the car's heading change is known from the GNSS/INS
// (RadarSample::ins_yaw_unwrapped = h), and the radar turns with the car, so
//   q(t) = R(h(t)) l u(theta),  u(a) = (cos a, sin a),
// is the detection in a frame fixed to the ground up to the unknown constant rotation psi (and the
// INS's mounting yaw, also constant): a static point P seen from the radar at c(t) has
//   q(t) = R(-psi') (P - c(t)),
// and a target moving at constant velocity moves in q at constant velocity while the radar does.
// Over the short window a track's prediction uses (association_window_s, about a second) the
// radar's path is close to straight, so a constant-velocity line through the track's recent q
// predicts where its next detection lies, for static and moving targets alike, in turns too.
//
// Per scan (detections of one time):
//  1. Prediction of each open track at the scan time: with one detection, its position (the
//     target's own motion unknown: the gate then allows the radar's speed plus
//     association_max_target_speed_mps across the line of sight, and the range predicted by the
//     range rate along it); with two or more, the least-squares line through its detections of
//     the last association_window_s.
//  2. Gate: the innovation's components along and across the new line of sight, each over its
//     predicted sigma (the nominal range noise along, range x azimuth noise across, inflated by
//     the line's uncertainty, plus association_model_sigma_m for what the constant-velocity model
//     misses), combined as a normalised distance <= association_gate_sigmas; and the range rate's
//     change since the track's last detection within what straight relative motion allows,
//     d(range rate)/dt = u_perp^2 / range in [0, (v + association_max_target_speed_mps)^2 / range]
//     (u_perp the relative speed across the line of sight, v the radar's speed), widened by
//     association_max_range_rate_jump_mps either way.
//  3. Assignment: pairs inside the gate in increasing distance, each track and detection once.
//     A detection left over starts a track; a track without a detection for more than
//     max_track_gap_s is closed.
// The ids are new integers 0, 1, ..., never re-used. Ghosts and clutter make tracks too; the
// position method drops them as it does a tracking radar's (short tracks, the triangle test).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"

namespace x2car::radar {

struct RadarAssociation {
  std::vector<int> track_of_sample;  // per sample: the track it joined, 0, 1, ...
  std::int64_t tracks = 0;           // tracks made (single detections included)
  std::int64_t tracks_of_two_or_more = 0;
};

// `samples` in time order (equal times: one scan). Reads their time, range, azimuth, range rate,
// ins_yaw_unwrapped and radar_velocity_in_vehicle; their track ids are ignored.
RadarAssociation associate_detections(std::span<const RadarSample> samples,
                                      const RadarPositionMethodOptions& options);

}  // namespace x2car::radar
