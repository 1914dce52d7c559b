#include "x2car/camera/ins_motion.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::camera {

void InsMotionOptions::Check() const {
  const OptionsCheck check("InsMotionOptions");
  check.finite("ins_to_frame_offset_s", ins_to_frame_offset_s);
  check.positive("max_record_gap_s", max_record_gap_s);
  check.positive("rate_span_s", rate_span_s);
  check.non_negative("min_reversing_speed_mps", min_reversing_speed_mps);
  check.that(min_heading_agreement > 0.0 && min_heading_agreement <= 1.0, "min_heading_agreement",
             "in (0, 1]");
  check.positive("min_course_turn", min_course_turn);
  check.non_negative("min_course_turning_s", min_course_turning_s);
}

namespace {

bool has_velocities(std::span<const io::InsRecord> records) {
  return std::ranges::any_of(records, [](const io::InsRecord& record) {
    return record.velocity_enu.head<2>().squaredNorm() > 0.0;
  });
}

// Horizontal velocity at record i [m/s]: its own, or its positions' central difference.
Eigen::Vector2d velocity_at(std::span<const io::InsRecord> records, std::size_t i,
                            bool velocities) {
  if (velocities) return records[i].velocity_enu.head<2>();
  const std::size_t before = i == 0 ? 0 : i - 1;
  const std::size_t after = std::min(records.size() - 1, i + 1);
  if (before == after) return Eigen::Vector2d::Zero();
  return (records[after].position_enu - records[before].position_enu).head<2>() /
         (records[after].time - records[before].time);
}

double speed_at(std::span<const io::InsRecord> records, std::size_t i, bool velocities) {
  return velocity_at(records, i, velocities).norm();
}

// Whether the log's heading turns with the car: where the course turns by min_course_turn or more
// over rate_span_s while the car moves (it cannot change between ahead and back without stopping),
// the heading must turn by as much, to within half, for most of that time. A heading that stays
// put (a constant, a frozen yaw) says nothing about which way the car faces: on a drive out and
// back along one road every record of one leg would read as backing up. Less than
// min_course_turning_s of such turning (a straight drive; a noisy record or two) cannot tell
// (true).
bool heading_turns_with_course(std::span<const io::InsRecord> records,
                               std::span<const double> courses,
                               std::span<const std::uint8_t> moving,
                               const InsMotionOptions& options) {
  double turning_s = 0.0;
  double following_s = 0.0;
  for (std::size_t i = 0; i + 1 < records.size(); ++i) {
    if (!moving[i]) continue;
    const auto later = std::ranges::lower_bound(records, records[i].time + options.rate_span_s, {},
                                                &io::InsRecord::time);
    if (later == records.end()) break;
    const auto j = static_cast<std::size_t>(later - records.begin());
    if (!moving[j] ||
        records[j].time - records[i].time > options.rate_span_s + options.max_record_gap_s) {
      continue;  // stopped, or a gap in the log
    }
    const double course_turn = angle_difference(courses[j], courses[i]);
    if (std::abs(course_turn) < options.min_course_turn) continue;
    const double step_s = std::min(records[i + 1].time - records[i].time, options.max_record_gap_s);
    turning_s += step_s;
    const double heading_turn = angle_difference(records[j].attitude.yaw, records[i].attitude.yaw);
    if (std::abs(heading_turn - course_turn) <= 0.5 * std::abs(course_turn)) following_s += step_s;
  }
  return turning_s < options.min_course_turning_s || 2.0 * following_s >= turning_s;
}

// 1 where the car backs up: its course is more than 90 deg from the one it has against the
// device's heading while it drives ahead (any mounting yaw of the device is the same offset
// throughout). The offsets of the moving records are taken as axes (doubled angles), on which
// driving ahead and backing up fall alike, whatever share each has; ahead is the end of the axis
// most moving records lie on (most of a drive goes forward). Nothing is flagged when the doubled
// offsets do not gather round their axis (mean resultant length below min_heading_agreement: a
// heading unrelated to the car) or when the heading does not turn with the course
// (heading_turns_with_course). A heading that copies the course flags nothing either: every
// record lies at the axis' ahead end.
std::vector<std::uint8_t> reversing_records(std::span<const io::InsRecord> records, bool velocities,
                                            const InsMotionOptions& options) {
  std::vector<double> courses(records.size(), 0.0);
  std::vector<double> offsets(records.size(), 0.0);
  std::vector<std::uint8_t> moving(records.size(), 0);
  std::vector<double> moving_offsets;
  for (std::size_t i = 0; i < records.size(); ++i) {
    const Eigen::Vector2d velocity = velocity_at(records, i, velocities);
    if (velocity.norm() < options.min_reversing_speed_mps) continue;
    moving[i] = 1;
    courses[i] = std::atan2(velocity.y(), velocity.x());
    offsets[i] = angle_difference(records[i].attitude.yaw, courses[i]);
    moving_offsets.push_back(offsets[i]);
  }
  std::vector<std::uint8_t> reversing(records.size(), 0);
  const std::optional<double> ahead =
      majority_axis_end(moving_offsets, options.min_heading_agreement);
  if (!ahead || !heading_turns_with_course(records, courses, moving, options)) return reversing;
  for (std::size_t i = 0; i < records.size(); ++i) {
    reversing[i] = moving[i] && std::abs(angle_difference(offsets[i], *ahead)) > kPi / 2.0;
  }
  return reversing;
}

// Whether most records within rate_span_s around `time` back up: one record's course, from a
// noisy velocity or positions' difference, must not end a steady stretch.
bool reversing_around(std::span<const io::InsRecord> records,
                      std::span<const std::uint8_t> reversing, double time,
                      const InsMotionOptions& options) {
  const double half = 0.5 * options.rate_span_s;
  const auto first = std::ranges::lower_bound(records, time - half, {}, &io::InsRecord::time);
  const auto last = std::ranges::upper_bound(records, time + half, {}, &io::InsRecord::time);
  const auto begin = static_cast<std::size_t>(first - records.begin());
  const auto end = static_cast<std::size_t>(last - records.begin());
  std::size_t backing = 0;
  for (std::size_t i = begin; i < end; ++i) backing += reversing[i];
  return end > begin && 2 * backing > end - begin;
}

// The horizontal speed at `time` on the log's clock, interpolated; nullopt outside the log or in a
// gap.
std::optional<double> speed_at_time(std::span<const io::InsRecord> records, double time,
                                    bool velocities, const InsMotionOptions& options) {
  const auto after = std::ranges::upper_bound(records, time, {}, &io::InsRecord::time);
  if (after == records.begin() || after == records.end()) return std::nullopt;
  const std::size_t i = static_cast<std::size_t>(after - records.begin()) - 1;
  const double span = records[i + 1].time - records[i].time;
  if (!(span > 0.0) || span > options.max_record_gap_s) return std::nullopt;
  const double share = (time - records[i].time) / span;
  return (1.0 - share) * speed_at(records, i, velocities) +
         share * speed_at(records, i + 1, velocities);
}

}  // namespace

std::vector<std::optional<VehicleMotion>> motion_from_ins(std::span<const double> frame_times,
                                                          std::span<const io::InsRecord> records,
                                                          const InsMotionOptions& options) {
  options.Check();
  std::vector<std::optional<VehicleMotion>> motion(frame_times.size());
  if (records.size() < 2) return motion;
  const bool velocities = has_velocities(records);
  const std::vector<std::uint8_t> reversing = reversing_records(records, velocities, options);
  for (std::size_t f = 0; f < frame_times.size(); ++f) {
    const double time = frame_times[f] - options.ins_to_frame_offset_s;  // on the log's clock
    const auto after = std::ranges::upper_bound(records, time, {}, &io::InsRecord::time);
    if (after == records.begin() || after == records.end()) continue;
    const std::size_t i = static_cast<std::size_t>(after - records.begin()) - 1;
    const double span = records[i + 1].time - records[i].time;
    if (!(span > 0.0) || span > options.max_record_gap_s) continue;
    const double share = (time - records[i].time) / span;
    const double half = 0.5 * options.rate_span_s;
    VehicleMotion at;
    at.speed_mps = (1.0 - share) * speed_at(records, i, velocities) +
                   share * speed_at(records, i + 1, velocities);
    // The yaw's rate over the same span: between two records 10 ms apart the heading's noise
    // (0.01-0.05 deg) would read as degrees per second.
    {
      const auto first = std::ranges::lower_bound(records, time - half, {}, &io::InsRecord::time);
      auto last = std::ranges::upper_bound(records, time + half, {}, &io::InsRecord::time);
      if (last != records.begin()) --last;
      const double apart = last->time - first->time;
      at.yaw_rate =
          apart > 0.0
              ? angle_difference(last->attitude.yaw, first->attitude.yaw) / apart
              : angle_difference(records[i + 1].attitude.yaw, records[i].attitude.yaw) / span;
    }
    // The acceleration over rate_span_s around the frame (where the log covers it): a
    // difference over one record's interval would be mostly the speed's noise.
    const std::optional<double> speed_before =
        speed_at_time(records, time - half, velocities, options);
    const std::optional<double> speed_after =
        speed_at_time(records, time + half, velocities, options);
    if (speed_before && speed_after) {
      at.acceleration_mps2 = (*speed_after - *speed_before) / options.rate_span_s;
    }
    at.reversing = reversing_around(records, reversing, time, options);
    motion[f] = at;
  }
  return motion;
}

}  // namespace x2car::camera
