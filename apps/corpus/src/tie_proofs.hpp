#pragma once
// Proofs for the tie-rule classes of accept_diff.hpp: re-execute the accepted program with an
// alternative tie choice or loop order (what the original's hash-order choices could have done)
// and see whether that yields the logged next world.
#include <optional>

#include "flipper/corpus/accept_diff.hpp"

namespace flipper::corpus::detail {

/// The class whose alternative re-execution reproduces `want`, trying in order: another item
/// choice (item_choice), another equally near cell (nearest_cell), another loop order
/// (loop_order, also combined with the other two); nullopt when none does.
std::optional<AcceptClass> prove_tie(const sdk::Program& program, const sdk::WorldState& start,
                                     const sdk::Planner& planner, const WorldSnapshot& want);

}  // namespace flipper::corpus::detail
