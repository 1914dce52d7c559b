#include "x2car/radar/radar_association.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "x2car/radar/radar_ego_motion.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::radar {
namespace {

namespace testing = sim::testing;

using testing::ConstructedTarget;
using testing::kRadarLeverArm;

std::vector<RadarSample> samples_of(const std::vector<io::RadarDetection>& detections,
                                    const std::vector<io::InsRecord>& ins) {
  return radar_ego_motion(detections, ins, kRadarLeverArm.head<2>()).samples;
}

// Exact detections of posts and of cars, without ids: each post and the car ahead become exactly
// one track, and no track holds two targets.
TEST(RadarAssociation, ExactTargetsBecomeOneTrackEach) {
  std::vector<ConstructedTarget> targets;
  for (int k = 0; k < 10; ++k) {
    targets.push_back({.position = {30.0 + 12.0 * k, k % 2 == 0 ? -5.0 : 7.0}, .track_id = k});
  }
  targets.push_back({.position = {25.0, 0.3}, .velocity = {11.0, 0.0}, .track_id = 20});
  targets.push_back({.position = {150.0, 3.5}, .velocity = {-9.0, 0.0}, .track_id = 21});
  testing::ConstructedRadarDrive drive =
      testing::constructed_radar_drive(10.0, 12.0, rad_from_deg(8.0), targets);
  std::vector<int> truth;
  for (io::RadarDetection& detection : drive.detections) {
    truth.push_back(detection.track_id);
    detection.track_id = io::kNoTrackId;
  }
  const std::vector<RadarSample> samples = samples_of(drive.detections, drive.ins);
  ASSERT_EQ(samples.size(), truth.size());
  const RadarAssociation association = associate_detections(samples, {});
  std::map<int, std::set<int>> targets_of_track;
  std::map<int, std::set<int>> tracks_of_target;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    targets_of_track[association.track_of_sample[i]].insert(truth[i]);
    tracks_of_target[truth[i]].insert(association.track_of_sample[i]);
  }
  for (const auto& [track, of] : targets_of_track) EXPECT_EQ(of.size(), 1u) << "track " << track;
  for (const auto& [target, of] : tracks_of_target) {
    // The oncoming car passes at 19 m/s relative, faster across the line of sight than the gate
    // of a new track allows (the radar's speed + 2 m/s): it may split, harmlessly.
    if (target != 21) {
      EXPECT_EQ(of.size(), 1u) << "target " << target;
    }
  }
  EXPECT_LE(association.tracks, 14);
}

// The simulated urban drive with clutter, ghosts, misses and movers, seen by a cluster radar in
// several directions: the tracks of five or more detections are nearly pure (their detections come
// from one scene object), and nearly all detections of objects seen five times or more land in
// such tracks.
TEST(RadarAssociation, SimulatedClustersFormPureTracksInEveryDirection) {
  const testing::RadarDrive& drive = testing::urban_radar_drive(1);
  sim::RadarOptions radar = sim::RadarOptions::conti_ars408();
  radar.track_ids = false;
  for (const double yaw_deg : {0.0, 90.0, 180.0, -25.0}) {
    SCOPED_TRACE(::testing::Message() << "yaw " << yaw_deg << " deg");
    const Eigen::Isometry3d vehicle_from_radar =
        make_transform(EulerAngles{.roll = 0.0, .pitch = 0.0, .yaw = rad_from_deg(yaw_deg)},
                       testing::radar_lever_arm_for_yaw(yaw_deg));
    const std::vector<sim::RadarScan> scans =
        sim::simulate_radar(drive.simulation.states, vehicle_from_radar, drive.scene, radar, 7);
    std::vector<io::RadarDetection> detections;
    std::vector<int> objects;
    for (const sim::RadarScan& scan : scans) {
      for (const sim::SimulatedRadarDetection& d : scan.detections) {
        ASSERT_EQ(d.measurement.track_id, io::kNoTrackId);
        detections.push_back(d.measurement);
        objects.push_back(d.source == sim::RadarSource::kTarget ? d.object_id : -1);
      }
    }
    const auto ego = radar_ego_motion(detections, drive.simulation.ins,
                                      testing::radar_lever_arm_for_yaw(yaw_deg).head<2>());
    ASSERT_EQ(ego.samples.size(), detections.size());
    const RadarAssociation association = associate_detections(ego.samples, {});
    std::map<int, std::map<int, int>> objects_of_track;  // track -> object -> detections
    for (std::size_t i = 0; i < detections.size(); ++i) {
      ++objects_of_track[association.track_of_sample[i]][objects[i]];
    }
    int in_long_tracks = 0;
    int majority = 0;
    for (const auto& [track, counts] : objects_of_track) {
      int total = 0;
      int most = 0;
      for (const auto& [object, count] : counts) {
        total += count;
        most = std::max(most, count);
      }
      if (total < 5) continue;
      in_long_tracks += total;
      majority += most;
    }
    // Detections of scene objects seen five times or more (clutter and short glimpses aside).
    int of_long_objects = 0;
    std::map<int, int> per_object;
    for (const int object : objects) ++per_object[object];
    for (const auto& [object, count] : per_object) {
      if (object >= 0 && count >= 5) of_long_objects += count;
    }
    ASSERT_GT(in_long_tracks, 1000);
    EXPECT_GE(static_cast<double>(majority) / in_long_tracks, 0.98);
    EXPECT_GE(in_long_tracks, 0.9 * of_long_objects);
  }
}

}  // namespace
}  // namespace x2car::radar
