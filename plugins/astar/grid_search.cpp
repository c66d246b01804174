#include "grid_search.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>

namespace flipper::plugins::astar {

using sdk::Cell;

bool GridSearch::prepare(const sdk::Geometry& g) {
  pad_ = {0, 0, 0};
  for (const Cell& o : g.neighbour_offsets()) {
    pad_.x = std::max(pad_.x, std::abs(o.x));
    pad_.y = std::max(pad_.y, std::abs(o.y));
    pad_.z = std::max(pad_.z, std::abs(o.z));
  }
  min_ = g.min();
  const auto sx = static_cast<std::int64_t>(g.size_x());
  const auto sy = static_cast<std::int64_t>(g.size_y());
  const auto sz = static_cast<std::int64_t>(g.size_z());
  px_ = sx + 2 * pad_.x;
  py_ = sy + 2 * pad_.y;
  pz_ = sz + 2 * pad_.z;
  const std::int64_t total = px_ * py_ * pz_;
  if (total >= std::numeric_limits<std::uint32_t>::max()) return false;
  const auto n = static_cast<std::size_t>(total);
  if (seen_.size() != n) {
    seen_.assign(n, 0);
    parent_.resize(n);
    goal_.assign(n, 0);
    target_.assign(n, -1);
    generation_ = 0;
  }
  passable_.assign(n, 0);
  const std::uint8_t* mask = g.free_mask().data();
  for (std::int64_t z = 0; z < sz; ++z)
    for (std::int64_t y = 0; y < sy; ++y) {
      std::uint8_t* dst = passable_.data() + pad_.x + px_ * ((y + pad_.y) + py_ * (z + pad_.z));
      std::memcpy(dst, mask + sx * (y + sy * z), static_cast<std::size_t>(sx));
    }
  deltas_.clear();
  for (const Cell& o : g.neighbour_offsets()) deltas_.push_back(o.x + px_ * (o.y + py_ * o.z));
  return true;
}

void GridSearch::block(const sdk::Area& avoid, Cell exempt) {
  const Cell max{min_.x + static_cast<std::int32_t>(px_ - 2 * pad_.x) - 1,
                 min_.y + static_cast<std::int32_t>(py_ - 2 * pad_.y) - 1,
                 min_.z + static_cast<std::int32_t>(pz_ - 2 * pad_.z) - 1};
  for (const Cell& c : avoid) {
    if (c == exempt || c.x < min_.x || c.y < min_.y || c.z < min_.z || c.x > max.x || c.y > max.y ||
        c.z > max.z)
      continue;
    passable_[index(c)] = 0;
  }
}

Cell GridSearch::cell(std::uint32_t i) const {
  const auto px = static_cast<std::uint64_t>(px_), py = static_cast<std::uint64_t>(py_);
  std::uint64_t v = i;
  Cell c;
  c.x = static_cast<std::int32_t>(v % px) - pad_.x + min_.x;
  v /= px;
  c.y = static_cast<std::int32_t>(v % py) - pad_.y + min_.y;
  v /= py;
  c.z = static_cast<std::int32_t>(v) - pad_.z + min_.z;
  return c;
}

std::uint32_t GridSearch::next_generation() {
  if (++generation_ == 0) {
    std::fill(seen_.begin(), seen_.end(), 0);
    generation_ = 1;
  }
  return generation_;
}

sdk::PathResult GridSearch::shortest_path(Cell start, const sdk::Area& goals,
                                          const sdk::StopCondition& stop, std::uint64_t budget) {
  sdk::PathResult r;
  // Goal marks: only cells the search could ever enter (in bounds and free).
  goal_cells_.clear();
  for (const Cell& c : goals) {
    const Cell rel{c.x - min_.x, c.y - min_.y, c.z - min_.z};
    if (rel.x < 0 || rel.y < 0 || rel.z < 0 || rel.x >= px_ - 2 * pad_.x ||
        rel.y >= py_ - 2 * pad_.y || rel.z >= pz_ - 2 * pad_.z)
      continue;
    const std::uint32_t i = index(c);
    if (!passable_[i] && c != start) continue;
    goal_[i] = 1;
    goal_cells_.push_back(i);
  }
  struct Reset {
    GridSearch& s;
    ~Reset() {
      for (std::uint32_t i : s.goal_cells_) s.goal_[i] = 0;
    }
  } reset{*this};
  if (goal_cells_.empty()) {
    r.status = sdk::PlanStatus::no_path;
    r.message = "no goal cell is free (walls, outside the bounds or avoided)";
    return r;
  }
  if (should_stop(0, stop, budget)) {
    r.status = sdk::PlanStatus::stopped;
    r.message = "stopped before the search began";
    return r;
  }
  const std::uint32_t s = index(start);
  if (goal_[s]) {
    r.status = sdk::PlanStatus::found;
    r.target = start;
    return r;
  }
  const std::uint32_t gen = next_generation();
  queue_.clear();
  queue_.push_back(s);
  seen_[s] = gen;
  std::size_t head = 0, layer_end = 1;
  std::uint32_t best = 0;
  bool found = false;
  std::uint64_t expansions = 0;
  const std::uint8_t* pass = passable_.data();
  std::uint32_t* seen = seen_.data();
  std::uint32_t* parent = parent_.data();
  const std::uint8_t* goal = goal_.data();
  while (head < queue_.size()) {
    if (head == layer_end) {
      if (found) break;  // the whole layer before the goals' layer has been expanded
      layer_end = queue_.size();
    }
    if (should_stop(expansions, stop, budget)) {
      r.status = sdk::PlanStatus::stopped;
      r.expansions = expansions;
      r.message = "stopped after " + std::to_string(expansions) + " expansions";
      return r;
    }
    const std::uint32_t u = queue_[head++];
    ++expansions;
    for (const std::int64_t d : deltas_) {
      const auto v = static_cast<std::uint32_t>(static_cast<std::int64_t>(u) + d);
      if (!pass[v] || seen[v] == gen) continue;
      seen[v] = gen;
      parent[v] = u;
      queue_.push_back(v);
      if (goal[v]) {
        // Equally near goals: the smallest (x, y, z) wins; the index order is not that order.
        if (!found || cell(v) < cell(best)) best = v;
        found = true;
      }
    }
  }
  r.expansions = expansions;
  if (!found) {
    r.status = sdk::PlanStatus::no_path;
    r.message = "no goal cell is reachable from " + sdk::to_string(start, 3);
    return r;
  }
  r.status = sdk::PlanStatus::found;
  r.target = cell(best);
  for (std::uint32_t v = best; v != s; v = parent[v]) r.path.push_back(cell(v));
  std::reverse(r.path.begin(), r.path.end());
  return r;
}

void GridSearch::set_targets(const std::vector<Cell>& cells) {
  clear_targets();
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const std::uint32_t i = index(cells[k]);
    target_[i] = static_cast<std::int32_t>(k);
    marked_.push_back(i);
  }
}

void GridSearch::clear_targets() {
  for (std::uint32_t i : marked_) target_[i] = -1;
  marked_.clear();
}

bool GridSearch::distances(Cell from, int source, std::int32_t* row, const sdk::StopCondition& stop,
                           std::uint64_t budget, std::uint64_t& expansions) {
  // Targets still wanted: those with a larger id than the source (the rest are known by symmetry).
  std::size_t wanted = 0;
  for (std::uint32_t i : marked_)
    if (target_[i] > source) ++wanted;
  const std::uint32_t s = index(from);
  const std::uint32_t gen = next_generation();
  queue_.clear();
  queue_.push_back(s);
  seen_[s] = gen;
  if (target_[s] >= 0) {
    row[target_[s]] = 0;
    if (target_[s] > source) --wanted;
  }
  std::size_t head = 0, layer_end = 1;
  std::int32_t layer = 0;
  const std::uint8_t* pass = passable_.data();
  std::uint32_t* seen = seen_.data();
  const std::int32_t* target = target_.data();
  while (head < queue_.size() && wanted > 0) {
    if (head == layer_end) {
      layer_end = queue_.size();
      ++layer;
    }
    if (should_stop(expansions, stop, budget)) return false;
    const std::uint32_t u = queue_[head++];
    ++expansions;
    for (const std::int64_t d : deltas_) {
      const auto v = static_cast<std::uint32_t>(static_cast<std::int64_t>(u) + d);
      if (!pass[v] || seen[v] == gen) continue;
      seen[v] = gen;
      queue_.push_back(v);
      if (const std::int32_t t = target[v]; t >= 0) {
        row[t] = layer + 1;
        if (t > source) --wanted;
      }
    }
  }
  return true;
}

}  // namespace flipper::plugins::astar
