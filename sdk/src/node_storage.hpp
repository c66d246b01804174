#pragma once
// Where the SDK's program nodes live (docs/sdk.md, "Programs"): every Node the SDK builds (make,
// make_num, make_word, make_hole, and the nodes a parse result's bytes are read into) is
// allocated here, so that destroying a program never recurses once per level. A node that dies
// hands its kids to a queue of its thread instead of destroying them itself; the outermost death
// empties the queue. A program of any depth is destroyed in constant stack, whatever the level
// the destroying code was compiled at (an instrumented -O0 caller needs several hundred bytes of
// stack a level for the recursive destructor, so 10,000 levels took more than a thread's 8 MiB).
#include <memory>

#include "flipper/sdk/ast.hpp"

namespace flipper::sdk::detail {

/// A new node holding `node`'s fields, destroyed without recursion.
std::shared_ptr<Node> new_node(Node node = {});

}  // namespace flipper::sdk::detail
