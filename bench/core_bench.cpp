// Speed of the core pieces every calibrator runs on a whole log: smoothing a GNSS/INS track with
// GCV, sampling its heading and curvature, and segmenting it. Reported per minute of 100 Hz data.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "x2car/core/planar_track.hpp"
#include "x2car/core/segmentation.hpp"

namespace x2car {
namespace {

struct SyntheticLog {
  std::vector<double> times, x, y;
};

// A drive of `minutes` at 100 Hz: straights and 50 m-radius arcs at 12 m/s, 2 cm position noise.
SyntheticLog make_log(int minutes) {
  SyntheticLog log;
  std::mt19937_64 generator(42);
  std::normal_distribution<double> noise(0.0, 0.02);
  const int samples = minutes * 60 * 100;
  double heading = 0.3, px = 0.0, py = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double t = i / 100.0;
    const double curvature = std::fmod(t, 40.0) < 30.0 ? 0.0 : 0.02;
    heading += 12.0 * curvature * 0.01;
    px += 12.0 * std::cos(heading) * 0.01;
    py += 12.0 * std::sin(heading) * 0.01;
    log.times.push_back(t);
    log.x.push_back(px + noise(generator));
    log.y.push_back(py + noise(generator));
  }
  return log;
}

// Adds the counter "per_minute": wall time per minute of recorded data (elapsed / iterations /
// minutes, printed as a time).
void report_time_per_minute(benchmark::State& state, double minutes) {
  state.counters["per_minute"] = benchmark::Counter(
      minutes, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_SmoothTrackWithGcv(benchmark::State& state) {
  const SyntheticLog log = make_log(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const PlanarTrack track = fit_planar_track(log.times, log.x, log.y, {});
    benchmark::DoNotOptimize(track);
  }
  report_time_per_minute(state, static_cast<double>(state.range(0)));
}
BENCHMARK(BM_SmoothTrackWithGcv)->Arg(1)->Arg(10)->Unit(benchmark::kMillisecond);

void BM_SampleAndSegmentTrack(benchmark::State& state) {
  const SyntheticLog log = make_log(static_cast<int>(state.range(0)));
  const PlanarTrack track = fit_planar_track(log.times, log.x, log.y, {});
  for (auto _ : state) {
    const PlanarTrackSamples samples = sample_planar_track(track, log.times);
    const Segmentation segmentation =
        segment_runs(samples.time, samples.speed, samples.curvature, {});
    benchmark::DoNotOptimize(segmentation);
  }
  report_time_per_minute(state, static_cast<double>(state.range(0)));
}
BENCHMARK(BM_SampleAndSegmentTrack)->Arg(10)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace x2car
