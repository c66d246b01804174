#pragma once
// make's checks of a node's operands (arity, presence, sorts), without building the node: for
// the check of a plugin's programs (answer_check.cpp), which asks of every node whether make
// would build it and needs no copy of it.
#include <vector>

#include "flipper/sdk/ast.hpp"

namespace flipper::sdk::detail {

/// Throws Error(bad_program) exactly when make(kind, kids) would throw, and with its message;
/// builds nothing, except for the two shapes make rewrites (a nested sequence, a word verb's
/// ItemAction), which it hands to make.
void check_operands(Kind kind, const std::vector<Program>& kids);

}  // namespace flipper::sdk::detail
