#include "cell_search.hpp"

#include <algorithm>
#include <cmath>

namespace flipper::plugins::ompl {

using sdk::Cell;

double distance(Cell a, Cell b) {
  const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

CellSearch::CellSearch(const sdk::Geometry& geometry, const sdk::Area* avoid, Cell start)
    : g_(geometry), start_(start), pass_(geometry.free_mask()) {
  const std::size_t n = g_.cell_count();
  if (avoid != nullptr)
    for (const Cell& c : *avoid)
      if (g_.in_bounds(c)) pass_[g_.index(c)] = 0;
  if (g_.in_bounds(start)) pass_[g_.index(start)] = 1;
  for (const Cell& o : g_.neighbour_offsets())
    step_.push_back(static_cast<std::int64_t>(o.x) +
                    static_cast<std::int64_t>(g_.size_x()) *
                        (o.y + static_cast<std::int64_t>(g_.size_y()) * o.z));
  seen_.assign(n, 0);
  parent_.assign(n, 0);
  queue_.reserve(n);
  reach_.assign(n, 0);
  if (!g_.in_bounds(start)) return;
  // Flood fill from the start (needs neighbour bounds checks: offsets wrap across rows).
  queue_.clear();
  queue_.push_back(static_cast<std::uint32_t>(g_.index(start)));
  reach_[queue_[0]] = 1;
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const Cell c = g_.cell_at(queue_[head]);
    for (const Cell& o : g_.neighbour_offsets()) {
      const Cell d = c + o;
      if (!g_.in_bounds(d)) continue;
      const std::size_t i = g_.index(d);
      if (pass_[i] && !reach_[i]) {
        reach_[i] = 1;
        queue_.push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
}

bool CellSearch::connect(Cell from, Cell to, int margin, std::vector<Cell>& out) {
  if (from == to) return true;
  if (!passable(from) || !passable(to)) return false;
  Cell lo = g_.min(), hi = g_.max();
  if (margin >= 0) {
    lo = {std::max(lo.x, std::min(from.x, to.x) - margin),
          std::max(lo.y, std::min(from.y, to.y) - margin),
          std::max(lo.z, std::min(from.z, to.z) - margin)};
    hi = {std::min(hi.x, std::max(from.x, to.x) + margin),
          std::min(hi.y, std::max(from.y, to.y) + margin),
          std::min(hi.z, std::max(from.z, to.z) + margin)};
  }
  auto inside = [&](Cell c) {
    return c.x >= lo.x && c.x <= hi.x && c.y >= lo.y && c.y <= hi.y && c.z >= lo.z && c.z <= hi.z;
  };
  if (++epoch_ == 0) {  // wrapped: restart the stamps
    std::fill(seen_.begin(), seen_.end(), 0);
    epoch_ = 1;
  }
  const auto src = static_cast<std::uint32_t>(g_.index(from));
  const auto dst = static_cast<std::uint32_t>(g_.index(to));
  queue_.clear();
  queue_.push_back(src);
  seen_[src] = epoch_;
  const auto& offsets = g_.neighbour_offsets();
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const std::uint32_t i = queue_[head];
    const Cell c = g_.cell_at(i);
    for (std::size_t k = 0; k < offsets.size(); ++k) {
      const Cell d = c + offsets[k];
      if (!inside(d)) continue;
      const auto j = static_cast<std::uint32_t>(static_cast<std::int64_t>(i) + step_[k]);
      if (seen_[j] == epoch_ || !pass_[j]) continue;
      seen_[j] = epoch_;
      parent_[j] = i;
      if (j == dst) {
        const std::size_t first = out.size();
        for (std::uint32_t v = dst; v != src; v = parent_[v]) out.push_back(g_.cell_at(v));
        std::reverse(out.begin() + static_cast<std::ptrdiff_t>(first), out.end());
        return true;
      }
      queue_.push_back(j);
    }
  }
  return false;
}

}  // namespace flipper::plugins::ompl
