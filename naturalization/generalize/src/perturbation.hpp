#pragma once
// Deterministic perturbations of a world for the optional extra equivalence checks.
#include <cstdint>
#include <vector>

#include "flipper/sdk/world.hpp"

namespace flipper::naturalization::generalize {

/// `count` perturbed copies of `world`, the same for the same seed. Perturbation k moves the
/// robot to another free cell (even k), moves each lying item with probability 1/3 to another
/// free cell — half of the time onto the robot's cell, so that pick/drop rewritings meet more
/// items — and, for k % 3 == 2, puts one lying item into the robot's hand. Every copy differs
/// from `world`. Empty when the world has fewer than two free cells.
std::vector<sdk::WorldState> perturb(const sdk::WorldState& world, int count, std::uint64_t seed);

}  // namespace flipper::naturalization::generalize
