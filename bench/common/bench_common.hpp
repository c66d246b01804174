#pragma once
// What several benchmarks share: the percentile they report and the studio's query mix.
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace flipper::bench {

/// The p-th percentile (0..1) of `v`, nearest rank on the sorted values; 0 for no values.
inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

/// Study-map utterances of the core language (docs/core-language.md §10 and the dev corpus): the
/// query mix of bench/studio and bench/isolation.
inline const std::vector<std::string> kStudyQueries = {
    "move left",
    "move up; move up",
    "visit room1",
    "visit world containing item is red",
    "visit world containing item is red; pick item is red",
    "visit [3, 8]",
    "visit room5 while avoiding room3",
    "repeat 3 times move right",
    "foreach area in [room1, room2] { visit area; drop item }",
    "if robot has item is blue drop item is blue",
    "visit room4; pick every item",
    "strict { move up; move up }",
    "while possible move down",
    "visit area with corners [0, 0] and [3, 1]",
    "move lfet",
    "foreach point in world containing item is green { visit point; pick every item }",
};

}  // namespace flipper::bench
