#include "x2car/sim/radar_tracks.hpp"

#include <iterator>
#include <stdexcept>

namespace x2car::sim {

RadarTracks::RadarTracks(int id_count) {
  if (id_count < 1) throw std::invalid_argument("RadarTracks: id_count must be at least 1");
  in_use_.assign(static_cast<std::size_t>(id_count), false);
  released_in_scan_.assign(static_cast<std::size_t>(id_count), -1);
}

void RadarTracks::begin_scan(long scan) {
  scan_ = scan;
  touched_.clear();
  std::erase_if(blocked_until_, [&](const auto& entry) { return entry.second <= scan_; });
}

void RadarTracks::touch(SourceKey source) { touched_.insert(source); }

bool RadarTracks::blocked(SourceKey source) const {
  const auto it = blocked_until_.find(source);
  return it != blocked_until_.end() && scan_ < it->second;
}

std::optional<TrackId> RadarTracks::hit(SourceKey source) {
  if (const auto it = tracks_.find(source); it != tracks_.end()) {
    it->second.misses = 0;
    return TrackId{it->second.id, false};
  }
  for (std::size_t id = 0; id < in_use_.size(); ++id) {
    if (in_use_[id] || released_in_scan_[id] == scan_) continue;
    in_use_[id] = true;
    tracks_.emplace(source, Track{static_cast<int>(id), 0});
    return TrackId{static_cast<int>(id), true};
  }
  return std::nullopt;
}

void RadarTracks::miss(SourceKey source, int max_coast) {
  const auto it = tracks_.find(source);
  if (it == tracks_.end()) return;
  if (++it->second.misses > max_coast) end(source);
}

void RadarTracks::break_track(SourceKey source, int lost_scans) {
  end(source);
  blocked_until_[source] = scan_ + lost_scans;
}

void RadarTracks::end_untouched() {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    const auto next = std::next(it);
    if (!touched_.contains(it->first)) end(it->first);
    it = next;
  }
}

void RadarTracks::end(SourceKey source) {
  const auto it = tracks_.find(source);
  if (it == tracks_.end()) return;
  const auto id = static_cast<std::size_t>(it->second.id);
  in_use_[id] = false;
  released_in_scan_[id] = scan_;
  tracks_.erase(it);
}

}  // namespace x2car::sim
