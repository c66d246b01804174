// Plugin answers checked where they enter the kernel (docs/plugins-untrusted.md): the plugin
// call through its PluginRef, then the SDK's one check of the answer
// (flipper/sdk/answer_check.hpp).
#include "flipper/kernel/plugin_checks.hpp"

#include <optional>
#include <string_view>

#include "flipper/kernel/isolation.hpp"
#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/answer_wire.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/scorer.hpp"

namespace flipper::kernel {

using sdk::Cell;

namespace {

// The answer a child sent, or plugin_crashed when it is not one whole answer.
template <class Result>
Result whole(const PluginId& plugin, const char* op, std::optional<Result> answer) {
  if (!answer)
    throw sdk::Error(kPluginCrashed,
                     plugin.label() + ": " + op + ": its process sent a malformed answer");
  return std::move(*answer);
}

// A plugin call as PluginRef::call makes it, in a child process when the ref says so.
// The answer crosses the pipe as sdk::host's bytes (flipper/sdk/answer_wire.hpp).
template <class Result, class T, class Call, class FromBytes>
Result isolable_call(const PluginRef<const T>& plugin, const char* op,
                     const sdk::StopCondition& stop, Call call, FromBytes from_bytes) {
  auto in_process = [&] { return plugin.call(op, [&](const T& p) { return call(p, stop); }); };
  if (plugin.isolation() != Isolation::process) return in_process();
  std::optional<std::string> bytes;
  {
    const detail::CallTimer timer(plugin.id(), op);
    const T& object = *plugin.borrow();
    bytes = detail::call_in_child(plugin.id(), op, stop, [&](const sdk::StopCondition& child_stop) {
      return sdk::host::to_bytes(call(object, child_stop));
    });
  }
  // No child could be started (descriptors or processes exhausted): in process, as documented.
  return bytes ? whole(plugin.id(), op, from_bytes(*bytes)) : in_process();
}

}  // namespace

void throw_invalid_output(const PluginId& plugin, const char* code, const std::string& what) {
  throw sdk::Error(code, plugin.label() + ": " + what);
}

sdk::PathResult checked_plan(const PluginRef<const sdk::Planner>& planner,
                             const sdk::Geometry& geometry, const sdk::PathRequest& request,
                             const sdk::StopCondition& stop) {
  sdk::PathResult r = isolable_call<sdk::PathResult>(
      planner, "plan", stop,
      [&](const sdk::Planner& p, const sdk::StopCondition& s) {
        return p.plan(geometry, request, s);
      },
      sdk::host::path_result_of);
  if (auto v = sdk::path_violation(geometry, request, r))
    throw_invalid_output(planner.id(), sdk::codes::kInvalidPlan, *v);
  return r;
}

sdk::TourResult checked_tour(const PluginRef<const sdk::Planner>& planner,
                             const sdk::Geometry& geometry, Cell start,
                             const std::vector<Cell>& points, const sdk::StopCondition& stop) {
  sdk::TourResult t = isolable_call<sdk::TourResult>(
      planner, "tour", stop,
      [&](const sdk::Planner& p, const sdk::StopCondition& s) {
        return p.tour(geometry, start, points, s);
      },
      sdk::host::tour_result_of);
  if (auto v = sdk::tour_violation(points.size(), t))
    throw_invalid_output(planner.id(), sdk::codes::kInvalidPlan, *v);
  return t;
}

sdk::ParseResult checked_parse(const PluginRef<const sdk::Parser>& parser,
                               const sdk::ParseRequest& request) {
  sdk::ParseResult r = isolable_call<sdk::ParseResult>(
      parser, "parse", request.stop,
      [&](const sdk::Parser& p, const sdk::StopCondition& s) {
        if (&s == &request.stop) return p.parse(request);
        sdk::ParseRequest in_child = request;  // the child's budget (isolation.hpp)
        in_child.stop = s;
        return p.parse(in_child);
      },
      sdk::host::parse_result_of);
  if (auto v = sdk::parse_violation(request, r))
    throw_invalid_output(parser.id(), v->code, v->what);
  return r;
}

std::optional<std::vector<sdk::WeightChange>> checked_state_weights(
    const PluginRef<sdk::Scorer>& scorer, const sdk::StateWeights& reader,
    const std::string& state) {
  auto read =
      scorer.call("state_weights", [&](const sdk::Scorer&) { return reader.state_weights(state); });
  if (read)
    if (auto v = sdk::state_weights_violation(state.size(), *read))
      throw_invalid_output(scorer.id(), sdk::codes::kInvalidWeights, "state_weights: " + *v);
  return read;
}

// docs/plugins-untrusted.md §6: the learnt weights cross as values (sdk::host::learnt_bytes).
void checked_learn(const PluginRef<sdk::Scorer>& scorer, const std::vector<sdk::Candidate>& all,
                   std::size_t accepted, const sdk::ScoreContext& ctx,
                   const sdk::StopCondition& stop) {
  auto learn = [&](sdk::Scorer& s) { s.learn(all, accepted, ctx); };
  std::optional<std::string> bytes;
  if (scorer.isolation() == Isolation::process && sdk::host::learns_apart(*scorer.borrow())) {
    const detail::CallTimer timer(scorer.id(), "learn");
    bytes = detail::call_in_child(scorer.id(), "learn", stop, [&](const sdk::StopCondition&) {
      learn(*scorer.borrow());
      return sdk::host::learnt_bytes(*scorer.borrow());
    });
  }
  if (!bytes) return scorer.call("learn", learn);
  if (!scorer.call("learn", [&](sdk::Scorer& s) { return sdk::host::apply_learnt(s, *bytes); }))
    throw sdk::Error(kPluginCrashed,
                     scorer.id().label() + ": learn: its process sent a malformed answer");
}

}  // namespace flipper::kernel
