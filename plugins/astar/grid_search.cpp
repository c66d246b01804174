#include "grid_search.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <type_traits>

namespace flipper::plugins::astar {

using sdk::Cell;

bool GridSearch::prepare(const sdk::Geometry& g) {
  const auto& offsets = g.neighbour_offsets();
  if (offsets.size() > 6) return false;  // directions are stored in three bits
  pad_ = {0, 0, 0};
  for (const Cell& o : offsets) {
    pad_.x = std::max(pad_.x, std::abs(o.x));
    pad_.y = std::max(pad_.y, std::abs(o.y));
    pad_.z = std::max(pad_.z, std::abs(o.z));
  }
  min_ = g.min();
  max_ = g.max();
  const auto sx = static_cast<std::int64_t>(g.size_x());
  const auto sy = static_cast<std::int64_t>(g.size_y());
  const auto sz = static_cast<std::int64_t>(g.size_z());
  px_ = sx + 2 * static_cast<std::int64_t>(pad_.x);
  py_ = sy + 2 * static_cast<std::int64_t>(pad_.y);
  pz_ = sz + 2 * static_cast<std::int64_t>(pad_.z);
  const std::int64_t total = px_ * py_ * pz_;
  if (total >= std::numeric_limits<std::uint32_t>::max()) return false;
  const auto n = static_cast<std::size_t>(total);
  state_.assign(n, kBlocked);
  const std::uint8_t* mask = g.free_mask().data();
  for (std::int64_t z = 0; z < sz; ++z)
    for (std::int64_t y = 0; y < sy; ++y) {
      std::uint8_t* dst = state_.data() + pad_.x + px_ * ((y + pad_.y) + py_ * (z + pad_.z));
      const std::uint8_t* src = mask + sx * (y + sy * z);
      for (std::int64_t x = 0; x < sx; ++x) dst[x] = src[x] != 0 ? kOpen : kBlocked;
    }
  deltas_.clear();
  for (const Cell& o : offsets) deltas_.push_back(o.x + px_ * (o.y + py_ * o.z));
  goal_cells_.clear();
  target_cells_.clear();
  // Every cell enters a search's queue at most once: a fixed buffer, no capacity checks.
  if (queue_.size() < n) queue_.resize(n);
  queue_len_ = 0;
  dirty_ = false;
  return true;
}

void GridSearch::block(const sdk::Area& avoid, Cell exempt) {
  for (const Cell& c : avoid)
    if (c != exempt && in_box(c)) state_[index(c)] = kBlocked;
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

void GridSearch::reset_reached() {
  std::uint8_t* st = state_.data();
  for (std::size_t k = 0; k < queue_len_; ++k)
    st[queue_[k]] = static_cast<std::uint8_t>((st[queue_[k]] & ~kStateMask) | kOpen);
  queue_len_ = 0;
}

void GridSearch::trace_path(std::uint32_t v, std::uint32_t root, std::vector<Cell>& path) const {
  for (; v != root; v = parent(v)) path.push_back(cell(v));
  std::reverse(path.begin(), path.end());
}

template <int K>
bool GridSearch::bfs_to_goals(std::uint32_t s, const sdk::StopCondition& stop, std::uint64_t budget,
                              std::uint32_t& best, bool& found, std::uint64_t& expansions) {
  std::uint8_t* st = state_.data();
  std::uint32_t* queue = queue_.data();
  std::size_t len = 0;
  queue[len++] = s;
  st[s] = static_cast<std::uint8_t>((st[s] & ~kStateMask) | kReachedBase);  // the root
  const std::int64_t* deltas = deltas_.data();
  const int k_count = K > 0 ? K : static_cast<int>(deltas_.size());
  const std::uint64_t limit = std::min(budget, stop.max_expansions);
  std::size_t head = 0, layer_end = 1;
  bool completed = true;
  while (head < len) {
    if (head == layer_end) {
      if (found) break;  // the whole layer before the goals' layer has been expanded
      layer_end = len;
    }
    if (expansions >= limit || ((expansions & 1023u) == 0 && stop.should_stop(expansions))) {
      completed = false;
      break;
    }
    const std::uint32_t u = queue[head++];
    ++expansions;
    for (int k = 0; k < k_count; ++k) {
      const auto v = static_cast<std::uint32_t>(static_cast<std::int64_t>(u) + deltas[k]);
      // Branch-free visit: walls are random, so a branch on them would be mispredicted.
      const std::uint8_t sv = st[v];
      const bool open = (sv & kStateMask) == kOpen;
      st[v] = open ? static_cast<std::uint8_t>((sv & ~kStateMask) | (kReachedBase + k)) : sv;
      queue[len] = v;
      len += open;
      if ((sv & (kGoal | kStateMask)) == (kGoal | kOpen)) {
        // Equally near goals: the smallest (x, y, z) wins; the index order is not that order.
        if (!found || cell(v) < cell(best)) best = v;
        found = true;
      }
    }
  }
  queue_len_ = len;
  return completed;
}

template <int K>
bool GridSearch::bfs_distances(std::uint32_t s, int source, std::size_t wanted, std::int32_t* row,
                               const sdk::StopCondition& stop, std::uint64_t budget,
                               std::uint64_t& expansions) {
  std::uint8_t* st = state_.data();
  std::uint32_t* queue = queue_.data();
  std::size_t len = 0;
  queue[len++] = s;
  st[s] = static_cast<std::uint8_t>((st[s] & ~kStateMask) | kReachedBase);
  const std::int64_t* deltas = deltas_.data();
  const int k_count = K > 0 ? K : static_cast<int>(deltas_.size());
  const std::int32_t* target_id = target_id_.data();
  const std::uint64_t limit = std::min(budget, stop.max_expansions);
  std::size_t head = 0, layer_end = 1;
  std::int32_t layer = 0;
  bool completed = true;
  while (head < len && wanted > 0) {
    if (head == layer_end) {
      layer_end = len;
      ++layer;
    }
    if (expansions >= limit || ((expansions & 1023u) == 0 && stop.should_stop(expansions))) {
      completed = false;
      break;
    }
    const std::uint32_t u = queue[head++];
    ++expansions;
    for (int k = 0; k < k_count; ++k) {
      const auto v = static_cast<std::uint32_t>(static_cast<std::int64_t>(u) + deltas[k]);
      const std::uint8_t sv = st[v];
      const bool open = (sv & kStateMask) == kOpen;
      st[v] = open ? static_cast<std::uint8_t>((sv & ~kStateMask) | kReachedBase) : sv;
      queue[len] = v;
      len += open;
      if ((sv & (kTarget | kStateMask)) == (kTarget | kOpen)) {
        const std::int32_t t = target_id[v];
        row[t] = layer + 1;
        if (t > source) --wanted;
      }
    }
  }
  queue_len_ = len;
  return completed;
}

template <class Search>
bool GridSearch::for_neighbour_count(Search&& search) const {
  switch (deltas_.size()) {
    case 4:
      return search(std::integral_constant<int, 4>{});
    case 6:
      return search(std::integral_constant<int, 6>{});
    default:
      return search(std::integral_constant<int, 0>{});
  }
}

namespace {

sdk::PathResult no_free_goal() {
  sdk::PathResult r;
  r.status = sdk::PlanStatus::no_path;
  r.message = "no goal cell is free (walls, outside the bounds or avoided)";
  return r;
}

sdk::PathResult stopped_before_search() {
  sdk::PathResult r;
  r.status = sdk::PlanStatus::stopped;
  r.message = "stopped before the search began";
  return r;
}

sdk::PathResult stopped_after(std::uint64_t expansions) {
  sdk::PathResult r;
  r.status = sdk::PlanStatus::stopped;
  r.expansions = expansions;
  r.message = "stopped after " + std::to_string(expansions) + " expansions";
  return r;
}

sdk::PathResult unreachable(Cell start, std::uint64_t expansions) {
  sdk::PathResult r;
  r.status = sdk::PlanStatus::no_path;
  r.expansions = expansions;
  r.message = "no goal cell is reachable from " + sdk::to_string(start, 3);
  return r;
}

sdk::PathResult found_at(Cell target, std::uint64_t expansions) {
  sdk::PathResult r;
  r.status = sdk::PlanStatus::found;
  r.target = target;
  r.expansions = expansions;
  return r;
}

}  // namespace

sdk::PathResult GridSearch::shortest_path(Cell start, const sdk::Area& goals,
                                          const sdk::StopCondition& stop, std::uint64_t budget) {
  std::uint8_t* st = state_.data();
  const std::uint32_t s = index(start);
  // The start is passable whatever the mask says (it is where the robot stands).
  st[s] = static_cast<std::uint8_t>((st[s] & ~kStateMask) | kOpen);
  // Goal flags only on cells the search could ever enter (free, not avoided) and the start.
  for (const Cell& c : goals) {
    if (!in_box(c)) continue;
    const std::uint32_t i = index(c);
    if ((st[i] & kStateMask) == kBlocked) continue;
    st[i] |= kGoal;
    goal_cells_.push_back(i);
  }
  // No clean-up afterwards: the grid is dirty until the next prepare(), which every plan call
  // does first (a fresh copy costs less than undoing a search that reached the whole grid).
  struct Forget {
    GridSearch& self;
    ~Forget() {
      self.goal_cells_.clear();
      self.queue_len_ = 0;
      self.dirty_ = true;
    }
  } forget{*this};
  if (goal_cells_.empty()) return no_free_goal();
  if (should_stop(0, stop, budget)) return stopped_before_search();
  if (st[s] & kGoal) return found_at(start, 0);
  std::uint32_t best = 0;
  std::uint64_t expansions = 0;
  bool found = false;
  const bool completed = for_neighbour_count([&](auto k) {
    return bfs_to_goals<decltype(k)::value>(s, stop, budget, best, found, expansions);
  });
  if (!completed) return stopped_after(expansions);
  if (!found) return unreachable(start, expansions);
  sdk::PathResult r = found_at(cell(best), expansions);
  trace_path(best, s, r.path);
  return r;
}

sdk::PathResult GridSearch::shortest_path_astar(Cell start, Cell goal,
                                                const sdk::StopCondition& stop,
                                                std::uint64_t budget) {
  std::uint8_t* st = state_.data();
  const std::uint32_t s = index(start);
  if (start == goal) return found_at(start, 0);
  if (!in_box(goal) || (st[index(goal)] & kStateMask) != kOpen) return no_free_goal();
  if (should_stop(0, stop, budget)) return stopped_before_search();
  if (g_.size() != state_.size()) g_.resize(state_.size());
  const std::uint32_t t = index(goal);
  auto h = [&](std::uint32_t i) {
    const Cell c = cell(i);
    return static_cast<std::uint32_t>(std::abs(c.x - goal.x) + std::abs(c.y - goal.y) +
                                      std::abs(c.z - goal.z));
  };
  const std::uint32_t f0 = h(s);
  for (auto& b : buckets_) b.clear();
  auto push = [&](std::uint32_t i, std::uint32_t f) {
    const std::size_t slot = f - f0;  // f never drops below f(start): h is consistent
    if (slot >= buckets_.size()) buckets_.resize(slot + 1);
    buckets_[slot].push_back(i);
  };
  queue_len_ = 0;  // every reached cell, for the reset
  st[s] = static_cast<std::uint8_t>((st[s] & ~kStateMask) | kReachedBase);
  g_[s] = 0;
  queue_[queue_len_++] = s;
  push(s, f0);
  struct Forget {
    GridSearch& self;
    ~Forget() {
      self.queue_len_ = 0;
      self.dirty_ = true;
    }
  } forget{*this};
  const std::int64_t* deltas = deltas_.data();
  const auto k_count = static_cast<std::uint8_t>(deltas_.size());
  std::uint64_t expansions = 0;
  bool found = false;
  for (std::size_t slot = 0; slot < buckets_.size() && !found; ++slot) {
    // Last in, first out within one f: deeper cells first, which keeps the frontier small.
    // (Indexed access: pushing may grow buckets_ and move the inner vectors.)
    while (!buckets_[slot].empty()) {
      const std::uint32_t u = buckets_[slot].back();
      buckets_[slot].pop_back();
      if (st[u] & kClosed) continue;  // a stale entry
      if (u == t) {
        found = true;
        break;
      }
      if (should_stop(expansions, stop, budget)) return stopped_after(expansions);
      st[u] |= kClosed;
      ++expansions;
      const std::uint32_t gu = g_[u] + 1;
      for (std::uint8_t k = 0; k < k_count; ++k) {
        const auto v = static_cast<std::uint32_t>(static_cast<std::int64_t>(u) + deltas[k]);
        const std::uint8_t sv = st[v];
        const std::uint8_t state = sv & kStateMask;
        if (state == kBlocked || (sv & kClosed)) continue;
        if (state != kOpen && g_[v] <= gu) continue;
        if (state == kOpen) queue_[queue_len_++] = v;
        st[v] = static_cast<std::uint8_t>((sv & ~kStateMask) | (kReachedBase + k));
        g_[v] = gu;
        push(v, gu + h(v));
      }
    }
  }
  if (!found) return unreachable(start, expansions);
  sdk::PathResult r = found_at(goal, expansions);
  trace_path(t, s, r.path);
  return r;
}

void GridSearch::set_goals(const std::vector<Cell>& cells) {
  for (const Cell& c : cells) {
    const std::uint32_t i = index(c);
    state_[i] |= kGoal;
    goal_cells_.push_back(i);
  }
}

void GridSearch::unset_goal(Cell c) {
  state_[index(c)] &= static_cast<std::uint8_t>(~kGoal);
}

std::int32_t GridSearch::nearest_goal(Cell from, Cell& goal, const sdk::StopCondition& stop,
                                      std::uint64_t budget, std::uint64_t& expansions,
                                      bool& stopped) {
  const std::uint32_t s = index(from);
  const std::uint8_t s0 = state_[s];
  state_[s] = static_cast<std::uint8_t>((s0 & ~kStateMask) | kOpen);
  std::uint32_t best = 0;
  bool found = false, completed = true;
  if (s0 & kGoal) {
    found = true;
    best = s;
  } else {
    completed = for_neighbour_count([&](auto k) {
      return bfs_to_goals<decltype(k)::value>(s, stop, budget, best, found, expansions);
    });
  }
  // Distance of the goal: walk its parents back before the marks are reset.
  std::int32_t d = 0;
  if (completed && found)
    for (std::uint32_t v = best; v != s; v = parent(v)) ++d;
  reset_reached();
  state_[s] = s0;
  stopped = !completed;
  if (!completed || !found) return -1;
  goal = cell(best);
  return d;
}

void GridSearch::set_targets(const std::vector<Cell>& cells) {
  clear_targets();
  if (target_id_.size() != state_.size()) target_id_.resize(state_.size());
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const std::uint32_t i = index(cells[k]);
    state_[i] |= kTarget;
    target_id_[i] = static_cast<std::int32_t>(k);
    target_cells_.push_back(i);
  }
}

void GridSearch::clear_targets() {
  for (std::uint32_t i : target_cells_) state_[i] &= static_cast<std::uint8_t>(~kTarget);
  target_cells_.clear();
}

bool GridSearch::distances(Cell from, int source, std::int32_t* row, const sdk::StopCondition& stop,
                           std::uint64_t budget, std::uint64_t& expansions) {
  std::uint8_t* st = state_.data();
  // Targets still wanted: those with a larger id than the source (the rest are known by symmetry).
  std::size_t wanted = target_cells_.size() - static_cast<std::size_t>(std::max(source + 1, 0));
  const std::uint32_t s = index(from);
  const std::uint8_t s0 = st[s];
  if (s0 & kTarget) {
    const std::int32_t t = target_id_[s];
    row[t] = 0;
    if (t > source) --wanted;
  }
  bool completed = true;
  if (wanted > 0)
    completed = for_neighbour_count([&](auto k) {
      return bfs_distances<decltype(k)::value>(s, source, wanted, row, stop, budget, expansions);
    });
  // The start cell is restored to what it was (it may be a wall in odd requests).
  reset_reached();
  st[s] = s0;
  return completed;
}

}  // namespace flipper::plugins::astar
