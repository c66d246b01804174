#pragma once
/// @file intervals.hpp
/// Confidence intervals over a benchmark's seeds (docs/planners.md §5, "Intervals"): a success
/// rate's Wilson score interval, and Student's t interval of a mean over seeds. Both are closed
/// formulas (no resampling), so the same rows give the same bounds on every machine.

#include <cstddef>
#include <optional>
#include <vector>

namespace flipper::planbench {

struct Interval {
  double low = 0, high = 0;
};

/// The two-sided normal quantile of a confidence level: 1.959963984540054 for 0.95.
double normal_quantile(double confidence);
/// The two-sided quantile of Student's t with `df` degrees of freedom (df ≥ 1): 4.302652729911275
/// for 0.95 and df = 2.
double t_quantile(double confidence, std::size_t df);

/// The Wilson score interval of `successes` out of `n` trials, as fractions (0..1):
/// (p + z²/2n ± z·sqrt(p(1−p)/n + z²/4n²)) / (1 + z²/n), clipped to [0, 1]; 7 of 10 at 0.95 is
/// [0.3968, 0.8922]. None for n = 0.
std::optional<Interval> wilson_interval(std::size_t successes, std::size_t n,
                                        double confidence = 0.95);

/// Student's t interval of the mean of `values` (one per seed): mean ± t(df = k−1)·sd/√k with
/// the sample standard deviation. None for fewer than two values.
std::optional<Interval> t_interval(const std::vector<double>& values, double confidence = 0.95);

}  // namespace flipper::planbench
