// Series cut to a size a browser draws at once (the report, issue 16 item 3: a 30-minute log's
// report stays under ~10 MB), keeping what a plot of them shows: each bucket of consecutive
// samples keeps its smallest and its largest value, in time order, so peaks and steps survive.
#pragma once

#include <cstddef>

#include "x2car/core/calibration_result.hpp"

namespace x2car::report {

// `series` with at most max_points samples (max_points >= 2; fewer when it already fits). An
// indexed series (no times) is cut the same way. Non-finite values are passed over in the choice
// of a bucket's extremes; a bucket with none finite keeps its first sample, so gaps stay gaps.
Series decimate_series(const Series& series, std::size_t max_points);

// `series` with at most max_points samples taken at an even stride: for series drawn against each
// other (x against y), whose samples must stay paired, so two series of one length keep the same
// indices. Non-finite values are kept.
Series thin_series(const Series& series, std::size_t max_points);

}  // namespace x2car::report
