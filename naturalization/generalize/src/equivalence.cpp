#include "equivalence.hpp"

#include <algorithm>

namespace flipper::naturalization::generalize {

namespace {

int dims_of(const sdk::WorldState& w) {
  return w.geometry ? w.geometry->dims() : 2;
}

std::string describe(const sdk::TraceStep& s, int dims) {
  switch (s.act) {
    case sdk::TraceStep::Act::move:
      return "move to " + sdk::to_string(s.cell, dims);
    case sdk::TraceStep::Act::pick:
    case sdk::TraceStep::Act::drop:
      return std::string(s.act == sdk::TraceStep::Act::pick ? "pick " : "drop ") + s.item.color +
             " " + s.item.shape + " at " + sdk::to_string(s.cell, dims);
  }
  return "?";
}

std::string world_difference(const sdk::WorldState& a, const sdk::WorldState& b) {
  const int dims = dims_of(a);
  if (a.robot != b.robot)
    return "robot at " + sdk::to_string(a.robot, dims) + " vs " + sdk::to_string(b.robot, dims);
  if (a.held != b.held)
    return "held items differ (" + std::to_string(a.held.size()) + " vs " +
           std::to_string(b.held.size()) + ")";
  if (a.items != b.items) return "lying items differ";
  return "rooms or geometry differ";
}

}  // namespace

std::optional<std::string> difference(const sdk::Outcome& body, const sdk::Outcome& candidate) {
  if (candidate.error) return "execution error: " + *candidate.error;
  if (body.error) return "execution error of the body: " + *body.error;
  const auto& t = body.trace;
  const auto& u = candidate.trace;
  if (t != u) {
    const auto mismatch = std::mismatch(t.begin(), t.end(), u.begin(), u.end());
    const auto i = static_cast<std::size_t>(mismatch.first - t.begin());
    const int dims = dims_of(body.world);
    const std::string b = i < t.size() ? describe(t[i], dims) : "no step";
    const std::string c = i < u.size() ? describe(u[i], dims) : "no step";
    return "different trace at step " + std::to_string(i + 1) + " (body: " + b +
           "; candidate: " + c + ")";
  }
  if (!body.world.same_state(candidate.world))
    return "different final world: " + world_difference(body.world, candidate.world);
  return std::nullopt;
}

}  // namespace flipper::naturalization::generalize
