#pragma once
/// @file accepted_plan.hpp
/// Observers of accepted plans: after a successful `accept` (world committed, scorer updated)
/// the session tells each observer what was executed. Front ends use it to send plans elsewhere
/// (e.g. apps/dds publishes them for robots); the kernel knows nothing about where they go.
/// An observer must not throw into the session: a failure is the observer's to report (the
/// session catches and logs anything thrown, the accept stands).

#include <cstdint>
#include <string>

#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/world.hpp"

namespace flipper::kernel {

struct AcceptedPlan {
  const sdk::WorldState& before;  ///< the world the candidate was executed on
  const sdk::Outcome& outcome;    ///< its trace and final world
  const std::string& formula;     ///< the candidate in canonical core-language text
  const std::string& user;
  std::uint64_t sequence = 0;  ///< 1, 2, ... per session
};

class AcceptedPlanObserver {
 public:
  virtual ~AcceptedPlanObserver() = default;
  virtual void on_accepted_plan(const AcceptedPlan& plan) = 0;
};

}  // namespace flipper::kernel
