#pragma once
// Where the SDK's program nodes live (docs/plugins-untrusted.md §6, step 2): every Node the SDK
// builds (make, make_num, make_word, make_hole, and the nodes a parse result's bytes are read into)
// is allocated here, so that destroying a program never recurses once per level. A dying node whose
// kids include an inner node that dies with it hands its kids to the queue of the outermost death
// on its thread instead of destroying them itself; that death empties the queue. A program of any
// depth is destroyed in constant stack, whatever level the destroying code was compiled at
// (instrumented at -O0, the recursive destructor took several hundred bytes of stack a level, and
// 10,000 levels more than a thread's 8 MiB).
#include <memory>

#include "flipper/sdk/ast.hpp"

namespace flipper::sdk::detail {

/// A new node holding `node`'s fields, destroyed without recursion.
std::shared_ptr<Node> new_node(Node node = {});

}  // namespace flipper::sdk::detail
