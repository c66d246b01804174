// Sweep grids and shards (docs/experiments.md §4).
#include "flipper/record/sweep.hpp"

#include <charconv>

#include "flipper/sdk/errors.hpp"

namespace flipper::record {

std::vector<std::vector<Assignment>> expand_grid(const std::vector<SweepAxis>& axes) {
  std::vector<std::vector<Assignment>> points{{}};
  for (const auto& axis : axes) {
    std::vector<std::vector<Assignment>> next;
    next.reserve(points.size() * axis.values.size());
    for (const auto& p : points)
      for (const auto& v : axis.values) {
        auto q = p;
        q.emplace_back(axis.key, v);
        next.push_back(std::move(q));
      }
    points = std::move(next);
  }
  return points;
}

std::string point_name(const std::vector<Assignment>& point) {
  std::string out;
  for (const auto& [key, value] : point) out += (out.empty() ? "" : ",") + key + "=" + value;
  return out;
}

bool is_seed_key(const std::string& key) {
  const std::string last = key.substr(key.rfind('.') == std::string::npos ? 0 : key.rfind('.') + 1);
  return last == "seed" || (last.size() > 5 && last.compare(last.size() - 5, 5, "_seed") == 0);
}

Shard parse_shard(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return sdk::Error(sdk::codes::kBadRequest, "--shard '" + text + "': " + why);
  };
  const auto slash = text.find('/');
  if (slash == std::string::npos) throw bad("expected I/N (e.g. 0/4: the first of four shards)");
  Shard s;
  const auto parse = [&](const std::string& part, int& out) {
    const auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), out);
    return ec == std::errc() && ptr == part.data() + part.size() && !part.empty();
  };
  if (!parse(text.substr(0, slash), s.index) || !parse(text.substr(slash + 1), s.count))
    throw bad("expected two whole numbers I/N");
  if (s.count < 1) throw bad("N must be at least 1");
  if (s.index < 0 || s.index >= s.count)
    throw bad("I must be from 0 to " + std::to_string(s.count - 1) +
              " (shards count from 0: a Slurm array of N tasks is --array=0-" +
              std::to_string(s.count - 1) + ")");
  return s;
}

}  // namespace flipper::record
