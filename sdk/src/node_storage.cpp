#include "node_storage.hpp"

#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace flipper::sdk::detail {
namespace {

/// Whether destroying `node` would destroy a kid that has kids of its own (the only case that
/// recurses): a kid shared elsewhere only loses a reference, and a leaf dies at once.
bool kills_an_inner_node(const Node& node) noexcept {
  for (const Program& kid : node.kids) {
    if (kid && kid.use_count() == 1 && !kid->kids.empty()) return true;
  }
  return false;
}

// The queue of this thread's outermost dying node while it empties it, else null. A plain
// pointer: a thread_local vector would be destroyed at exit before the statics whose programs die
// after it, and their deaths would then push into freed memory.
thread_local std::vector<Program>* draining = nullptr;

/// Moves `node`'s kids to the queue of the outermost death on this thread, or, being that death,
/// to a queue of its own that it empties. Without memory for the queue, the kids left in place are
/// destroyed by the node's own destructor, recursively, as std::shared_ptr would.
void release_kids(Node& node) noexcept {
  if (!kills_an_inner_node(node)) return;  // the common case, without thread-local storage
  std::vector<Program>* const outer = draining;
  std::vector<Program> own;
  std::vector<Program>& queue = outer != nullptr ? *outer : own;
  try {
    for (Program& kid : node.kids) {
      if (kid) queue.push_back(std::move(kid));
    }
  } catch (const std::bad_alloc&) {
  }
  if (outer != nullptr) return;
  draining = &own;
  while (!own.empty()) {
    // The last reference dies at the end of this block: its node's kids join the queue.
    Program kid = std::move(own.back());
    own.pop_back();
  }
  draining = nullptr;
}

/// std::allocator, except that a Node's kids are released (release_kids) before it is destroyed.
template <class T>
struct NodeAllocator {
  using value_type = T;
  NodeAllocator() = default;
  template <class U>
  NodeAllocator(const NodeAllocator<U>& /*other*/) noexcept {}  // implicit, as allocators convert
  T* allocate(std::size_t n) { return std::allocator<T>{}.allocate(n); }
  void deallocate(T* p, std::size_t n) noexcept { std::allocator<T>{}.deallocate(p, n); }
  template <class U>
  void destroy(U* p) noexcept {
    if constexpr (std::is_same_v<std::remove_cv_t<U>, Node>) release_kids(*p);
    p->~U();
  }
  friend bool operator==(const NodeAllocator& /*a*/, const NodeAllocator& /*b*/) { return true; }
};

}  // namespace

std::shared_ptr<Node> new_node(Node node) {
  return std::allocate_shared<Node>(NodeAllocator<Node>{}, std::move(node));
}

}  // namespace flipper::sdk::detail
