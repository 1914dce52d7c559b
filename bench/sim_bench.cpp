// Speed of the simulator's vehicle motion: the longest route (highway, ~21 km) driven for 10 min
// at the full 100 Hz rate (route + motion; ~0.08 s in release on one core, was asserted < 0.5 s
// in a unit test).
#include <benchmark/benchmark.h>

#include "x2car/sim/route.hpp"
#include "x2car/sim/vehicle_motion.hpp"

namespace x2car {
namespace {

void BM_VehicleMotionTenMinutesHighway(benchmark::State& state) {
  const sim::VehicleMotionOptions options;
  for (auto _ : state) {
    const sim::Route route = sim::generate_route(
        sim::Scenario::kHighway, sim::route_length_for(sim::Scenario::kHighway, 600.0, options), 1);
    const sim::VehicleStates states =
        sim::simulate_vehicle_motion(route, sim::Scenario::kHighway, 600.0, options, 1);
    benchmark::DoNotOptimize(states);
  }
  state.counters["per_minute"] = benchmark::Counter(
      10.0, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_VehicleMotionTenMinutesHighway)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace x2car
