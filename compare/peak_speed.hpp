#pragma once
// The peak tip speed of docs/model.md §3 ("the peak speed over 0.5 time units"), as one function: measure.cpp's
// c_transient_peak (edge loading) and the front_spectrum study's c_peak (homogeneous loading, from the series) use it.
// Its own header, not measure.hpp, which most of the code includes.
#include <span>

namespace slipfront::compare {

/// Where and how fast the tip ran fastest.
struct PeakSpeed {
  double c = 0.0;  ///< the largest (x_j − x_i)/(t_j − t_i); NaN without a pair of samples `span` apart
  double x = 0.0;  ///< x_i of that window (its start); NaN with c
  double t = 0.0;  ///< t_i of that window
};

/// Tip samples (t, x) in time order, finite: for every sample i, j is the first sample with t_j ≥ t_i + span
/// (to 1e-12), and the window's speed is (x_j − x_i)/(t_j − t_i); windows that the samples do not close are not
/// formed. Returns the fastest window (the first of equals).
PeakSpeed peak_tip_speed(std::span<const double> t, std::span<const double> x, double span);

}  // namespace slipfront::compare
