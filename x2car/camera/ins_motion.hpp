// The car's motion at each camera frame from a GNSS/INS log, for the temporal filter's motion gate
// (temporal_filter.hpp; issue 14: `--ins FILE` gates by speed and yaw rate).
//
// Speed is the horizontal speed of the device's velocity (or, for a log without velocities, of its
// positions' differences), interpolated linearly at the frame's time; the yaw rate is the change
// of the device's yaw (wrapped) and the acceleration the change of the speed, each over
// rate_span_s centred on the frame. A device mounted at any yaw turns with the car, so its yaw rate
// is the car's (within the cosine of its small roll and pitch). The car backs up where its course
// is turned by more than 90 deg from the one it has against the device's heading driving ahead
// (the end of the offsets' axis that most moving records lie on: most of a drive goes forward),
// in most records within rate_span_s around the frame; never where the log's heading does not turn
// with the car.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "x2car/camera/temporal_filter.hpp"
#include "x2car/io/ins_csv.hpp"

namespace x2car::camera {

struct InsMotionOptions {
  // Seconds to add to a record's time to put it on the frames' clock (e.g. the log's
  // start_unix_time when the frames carry Unix times and the records times from the log's start).
  double ins_to_frame_offset_s = 0.0;
  // Records further apart than this around a frame give it no motion (a gap in the log) [s].
  double max_record_gap_s = 1.0;
  // The yaw rate and the acceleration are the yaw's and the speed's change over this span centred
  // on the frame (within the log) [s]: over one record's interval they would be mostly noise.
  double rate_span_s = 0.5;
  // Backing up (VehicleMotion::reversing) is told only at this speed or more [m/s]: slower, the
  // course is noise (a log without velocities: 2 cm of position noise differenced over 20 ms reads
  // as 1 m/s), and the motion gate's min_speed_mps refuses such frames anyway.
  double min_reversing_speed_mps = 2.0;
  // ... and only when the moving records' offsets of heading against course lie this close to one
  // axis (the mean resultant length of the doubled offsets, in (0, 1]: ahead and backing up fall on
  // the same axis) ...
  double min_heading_agreement = 0.5;
  // ... and when, where the course turns by this much or more over rate_span_s, the heading turns
  // alike for most of that time [rad]: a heading that stays put (a constant, a frozen yaw) does not
  // say which way the car faces ...
  double min_course_turn = rad_from_deg(5.0);
  // ... judged when the course turns for this long or longer [s] (shorter: a straight drive, or a
  // noisy record or two; the heading is trusted).
  double min_course_turning_s = 2.0;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// One entry per frame time; nullopt where the log does not cover the frame (before its first or
// after its last record, or in a gap). Records must be in strictly increasing time (as the
// readers give them).
std::vector<std::optional<VehicleMotion>> motion_from_ins(std::span<const double> frame_times,
                                                          std::span<const io::InsRecord> records,
                                                          const InsMotionOptions& options = {});

}  // namespace x2car::camera
