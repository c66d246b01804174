#include "perturbation.hpp"

#include <random>

namespace flipper::naturalization::generalize {

namespace {

// std::uniform_int_distribution differs between standard libraries; plain modulo keeps the
// perturbations identical everywhere (the bias is negligible for world sizes).
std::size_t below(std::mt19937_64& rng, std::size_t n) {
  return static_cast<std::size_t>(rng() % n);
}

}  // namespace

std::vector<sdk::WorldState> perturb(const sdk::WorldState& world, int count, std::uint64_t seed) {
  std::vector<sdk::WorldState> out;
  if (!world.geometry || count <= 0) return out;
  const sdk::Area& free = world.geometry->free_cells();
  if (free.size() < 2) return out;
  out.reserve(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    std::mt19937_64 rng(seed + 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(k + 1));
    sdk::WorldState w = world;
    bool changed = false;
    if (k % 2 == 0) {
      std::size_t i = below(rng, free.size());
      if (free[i] == w.robot) i = (i + 1 + below(rng, free.size() - 1)) % free.size();
      const sdk::Cell c = free[i];
      changed = changed || c != w.robot;
      w.robot = c;
    }
    for (auto& lying : w.items) {
      if (below(rng, 3) != 0) continue;
      const sdk::Cell to = below(rng, 2) == 0 ? w.robot : free[below(rng, free.size())];
      changed = changed || to != lying.at;
      lying.at = to;
    }
    if (k % 3 == 2 && !w.items.empty()) {
      const std::size_t i = below(rng, w.items.size());
      w.held.push_back(w.items[i].item);
      w.items.erase(w.items.begin() + static_cast<std::ptrdiff_t>(i));
      changed = true;
    }
    if (!changed) {
      // Guarantee a difference: move the robot one free cell along the sorted free list.
      for (std::size_t i = 0; i < free.size(); ++i)
        if (free[i] == w.robot) {
          w.robot = free[(i + 1) % free.size()];
          break;
        }
    }
    out.push_back(std::move(w));
  }
  return out;
}

}  // namespace flipper::naturalization::generalize
