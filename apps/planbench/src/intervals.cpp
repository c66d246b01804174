// Confidence intervals over seeds (docs/planners.md §5, "Intervals"): Boost.Math's normal and
// Student's t quantiles, the Wilson score interval and the t interval of a mean.
#include "flipper/planbench/intervals.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>

#include "stats.hpp"

namespace flipper::planbench {

double normal_quantile(double confidence) {
  return boost::math::quantile(boost::math::normal_distribution<double>(),
                               1 - (1 - confidence) / 2);
}

double t_quantile(double confidence, std::size_t df) {
  return boost::math::quantile(
      boost::math::students_t_distribution<double>(static_cast<double>(df)),
      1 - (1 - confidence) / 2);
}

std::optional<Interval> wilson_interval(std::size_t successes, std::size_t n, double confidence) {
  if (n == 0) return std::nullopt;
  const double z = normal_quantile(confidence), nn = static_cast<double>(n);
  const double p = static_cast<double>(successes) / nn, z2 = z * z;
  const double centre = (p + z2 / (2 * nn)) / (1 + z2 / nn);
  const double half = z * std::sqrt(p * (1 - p) / nn + z2 / (4 * nn * nn)) / (1 + z2 / nn);
  return Interval{std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

std::optional<Interval> t_interval(const std::vector<double>& values, double confidence) {
  if (values.size() < 2) return std::nullopt;
  const double m = stats::mean(values);
  const double half = t_quantile(confidence, values.size() - 1) * stats::sd(values) /
                      std::sqrt(static_cast<double>(values.size()));
  return Interval{m - half, m + half};
}

}  // namespace flipper::planbench
