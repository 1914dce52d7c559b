// Track-id bookkeeping of the simulated radar (radar_model.hpp, step 4): which source holds which
// id, coasting through missed scans, breaks, and re-use of freed ids.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace x2car::sim {

// What an echo comes from, as one ordered key: the kind in bits 56-59, a ghost flag in bit 62,
// the index within its kind below.
enum class SourceKind : std::uint64_t { kReflector = 0, kMover = 1, kClutter = 2 };
using SourceKey = std::uint64_t;

constexpr SourceKey source_key(SourceKind kind, std::size_t index) {
  return (static_cast<std::uint64_t>(kind) << 56) | static_cast<std::uint64_t>(index);
}
// The key of the multipath ghost of a target.
constexpr SourceKey ghost_key(SourceKey target) { return target | (std::uint64_t{1} << 62); }

struct TrackId {
  int id = 0;
  bool is_new = false;  // the track starts in this scan
};

class RadarTracks {
 public:
  // Ids 0 .. id_count - 1. Throws std::invalid_argument when id_count < 1.
  explicit RadarTracks(int id_count);

  // Starts a scan: forgets which sources were in view and the breaks that are over.
  void begin_scan(long scan);
  // The source is in view in this scan (its track is not ended by end_untouched).
  void touch(SourceKey source);
  bool has_track(SourceKey source) const { return tracks_.contains(source); }
  // Whether the source is lost after a break (it gets no track until the break is over).
  bool blocked(SourceKey source) const;

  // The source was detected: its track's id, or a new track with the lowest free id not freed in
  // this scan; nullopt when every id is taken.
  std::optional<TrackId> hit(SourceKey source);
  // The source was not detected: its track coasts, and ends after more than max_coast misses in a
  // row.
  void miss(SourceKey source, int max_coast);
  // Ends the source's track and blocks the source for `lost_scans` scans, this one included.
  void break_track(SourceKey source, int lost_scans);
  // Ends the tracks of sources not touched in this scan (they left the view, or their ghost died).
  void end_untouched();

  std::size_t active_tracks() const { return tracks_.size(); }

 private:
  struct Track {
    int id = 0;
    int misses = 0;  // in a row
  };
  void end(SourceKey source);

  std::map<SourceKey, Track> tracks_;
  std::map<SourceKey, long> blocked_until_;  // blocked while scan < this
  std::set<SourceKey> touched_;
  std::vector<bool> in_use_;
  std::vector<long> released_in_scan_;  // per id; -1 = never
  long scan_ = -1;
};

}  // namespace x2car::sim
