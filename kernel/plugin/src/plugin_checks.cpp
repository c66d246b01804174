// Plugin answers checked where they enter the kernel (docs/plugins-untrusted.md): the plugin
// call through its PluginRef, then the SDK's one check of the answer
// (flipper/sdk/answer_check.hpp).
#include "flipper/kernel/plugin_checks.hpp"

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <string_view>
#include <type_traits>

#include "flipper/kernel/isolation.hpp"
#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/answer_wire.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"
#include "flipper/sdk/scorer.hpp"
#include "flipper/toolkit/process/call_tape.hpp"

namespace flipper::kernel {

using sdk::Cell;
using toolkit::process::CallTape;

namespace {

// The answer a child sent, or plugin_crashed when it is not one whole answer.
template <class Result>
Result whole(const PluginId& plugin, const char* op, std::optional<Result> answer) {
  if (!answer)
    throw sdk::Error(kPluginCrashed,
                     plugin.label() + ": " + op + ": its process sent a malformed answer");
  return std::move(*answer);
}

// What a planner call is asked, as a number: the key of its record on a call tape (`op`, the
// geometry's address, which a fork keeps, the start, the cells of its areas).
std::uint64_t call_key(char op, const sdk::Geometry& geometry, Cell start,
                       const std::vector<Cell>* a, const std::vector<Cell>* b) {
  std::string bytes(1, op);
  auto add = [&](const void* p, std::size_t n) { bytes.append(static_cast<const char*>(p), n); };
  const sdk::Geometry* where = &geometry;
  add(static_cast<const void*>(&where), sizeof where);
  add(&start, sizeof start);
  for (const std::vector<Cell>* v : {a, b}) {
    const std::size_t n = v == nullptr ? ~std::size_t{0} : v->size();
    add(&n, sizeof n);
    if (v != nullptr) add(v->data(), n * sizeof(Cell));  // three 32-bit numbers, no padding
  }
  return std::hash<std::string>{}(bytes) | 1U;  // never 0, which no call has
}

// A planner call on a thread with a call tape (docs/plugins-untrusted.md §6, "One child per
// execution"), `key` what it is asked: a probe makes the first as without a tape (nullopt) and
// gives up at the second; a recording child makes it in process and sends its record; a replay
// takes the recorded answer (charged, then checked by the caller as a child's) or the recording
// child's end when it died in this call, and once it has left the recording, nullopt: the call
// is made as without a tape.
template <class Result, class T, class InProcess, class FromBytes>
std::optional<Result> taped_call(CallTape& tape, const PluginRef<const T>& plugin, const char* op,
                                 std::uint64_t key, InProcess in_process, FromBytes from_bytes) {
  using toolkit::process::kBegun;
  if (tape.mode() == CallTape::Mode::probe) {
    if (tape.probe_call()) return std::nullopt;
    throw sdk::Error(sdk::codes::kInternal, "a second planner call: the execution runs in a child");
  }
  if (tape.mode() == CallTape::Mode::record) {
    auto send = [&tape](const toolkit::process::TapeRecord& record) {
      const std::string bytes = CallTape::bytes_of(record);
      detail::send_part(bytes);
      tape.count_sent(bytes.size());
    };
    if (tape.sent() > detail::kMaxTapeBytes) ::_exit(0);  // the tape ends: one by one from here
    send({key, {}, kBegun, {}});
    toolkit::process::TapeRecord r{key, {}, 'A', {}};
    const auto start = sdk::cpu_time();
    try {
      Result result = in_process();
      r.bytes = sdk::host::to_bytes(result);
      r.cpu = sdk::cpu_time() - start;
      send(r);
      return result;
    } catch (...) {
      r = {key, sdk::cpu_time() - start, 'E', detail::failure_bytes(plugin.id(), op).value_or("")};
      send(r);
      throw;
    }
  }
  const std::optional<toolkit::process::TapeRecord> r = tape.take(key);
  if (!r || (r->tag == kBegun && !tape.end())) return std::nullopt;
  if (r->tag == kBegun) detail::rethrow_as_call(tape.end(), plugin.id(), op);  // died in it
  const detail::CallTimer timer(plugin.id(), op);
  charge_cpu(r->cpu);
  if (r->tag != 'A') detail::throw_failure(plugin.id(), op, r->bytes);
  return whole(plugin.id(), op, from_bytes(r->bytes));
}

// A plugin call as PluginRef::call makes it, in a child process when the ref says so.
// The answer crosses the pipe as sdk::host's bytes (flipper/sdk/answer_wire.hpp). A planner's
// call gives `key_of` (what it is asked, as a number), read only when the thread has a call tape
// (taped_call).
template <class Result, class T, class Call, class FromBytes, class KeyOf = std::nullptr_t>
Result isolable_call(const PluginRef<const T>& plugin, const char* op,
                     const sdk::StopCondition& stop, Call call, FromBytes from_bytes,
                     KeyOf key_of = nullptr) {
  auto in_process = [&] { return plugin.call(op, [&](const T& p) { return call(p, stop); }); };
  if (plugin.isolation() != Isolation::process) return in_process();
  if constexpr (!std::is_same_v<KeyOf, std::nullptr_t>) {
    if (CallTape* tape = CallTape::current())
      if (auto r = taped_call<Result>(*tape, plugin, op, key_of(), in_process, from_bytes))
        return std::move(*r);
  }
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
      sdk::host::path_result_of,
      [&] { return call_key('p', geometry, request.start, request.goals, request.avoid); });
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
      sdk::host::tour_result_of, [&] { return call_key('t', geometry, start, &points, nullptr); });
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

namespace {

// A series' answer (checked_parses): per parse, 'A' and its result's bytes or 'E' and its
// failure's bytes (the last), each after its length (8 bytes, this machine's byte order).
void append_frame(std::string& out, char tag, const std::string& payload) {
  const std::uint64_t length = payload.size() + 1;
  out.append(reinterpret_cast<const char*>(&length), sizeof length);  // NOLINT: its bytes
  out.push_back(tag);
  out += payload;
}

// The whole frames at the front of `bytes` as outcomes, at most one per request, ending at the
// first failure; `whole` says whether they are a whole series (see below).
std::vector<ParseOutcome> outcomes_of(const PluginRef<const sdk::Parser>& parser,
                                      const std::vector<sdk::ParseRequest>& requests,
                                      std::string_view bytes, bool& whole) {
  std::vector<ParseOutcome> out;
  whole = false;
  while (bytes.size() >= sizeof(std::uint64_t) && out.size() < requests.size()) {
    std::uint64_t length = 0;
    std::memcpy(&length, bytes.data(), sizeof length);
    if (length == 0 || length > bytes.size() - sizeof length) return out;
    const char tag = bytes[sizeof length];
    const std::string_view payload = bytes.substr(sizeof length + 1, length - 1);
    ParseOutcome o;
    if (tag == 'A') {
      auto result = sdk::host::parse_result_of(payload);
      if (!result) return out;
      o.result = std::move(*result);
      if (auto v = sdk::parse_violation(requests[out.size()], o.result)) {
        try {
          throw_invalid_output(parser.id(), v->code, v->what);
        } catch (...) {
          o.error = std::current_exception();
        }
      }
    } else if (tag == 'E') {
      try {
        detail::throw_failure(parser.id(), "parse", payload);
      } catch (...) {
        o.error = std::current_exception();
      }
    } else {
      return out;
    }
    bytes.remove_prefix(sizeof length + length);
    const bool failed = o.error != nullptr;
    out.push_back(std::move(o));
    if (failed) break;
  }
  // Ended by a failure (the child's, or the parent's check of an answer: the parses the child
  // made after it are dropped, as they would not have been made), or every parse answered.
  whole = (!out.empty() && out.back().error != nullptr) ||
          (bytes.empty() && out.size() == requests.size());
  return out;
}

}  // namespace

std::vector<ParseOutcome> checked_parses(const PluginRef<const sdk::Parser>& parser,
                                         const std::vector<sdk::ParseRequest>& requests,
                                         const sdk::StopCondition& stop) {
  auto one_by_one = [&] {
    std::vector<ParseOutcome> out;
    for (const auto& request : requests) {
      ParseOutcome o;
      try {
        o.result = checked_parse(parser, request);
      } catch (...) {
        o.error = std::current_exception();
      }
      const bool failed = o.error != nullptr;
      out.push_back(std::move(o));
      if (failed) break;
    }
    return out;
  };
  if (parser.isolation() != Isolation::process || requests.size() < 2) return one_by_one();
  // One child for the series; each parse's frame is sent as soon as it is made (send_part), so
  // that a child that dies midway has sent the outcomes of the parses before it.
  std::optional<std::string> bytes;
  std::string received;
  try {
    const detail::CallTimer timer(parser.id(), "parse");
    const sdk::Parser& object = *parser.borrow();
    bytes = detail::call_in_child(
        parser.id(), "parse", stop,
        [&](const sdk::StopCondition& s) {
          for (const auto& request : requests) {
            std::string frame;
            try {
              sdk::ParseRequest in_child = request;  // the child's budget (isolation.hpp)
              in_child.stop = s;
              append_frame(frame, 'A', sdk::host::to_bytes(object.parse(in_child)));
            } catch (...) {
              // Its failure ends the series (none to send: the parent sees a malformed one).
              if (auto failure = detail::failure_bytes(parser.id(), "parse"))
                append_frame(frame, 'E', *failure);
              detail::send_part(frame);
              break;
            }
            detail::send_part(frame);
          }
          return std::string();
        },
        &received);
  } catch (const sdk::Error& e) {
    if (std::string_view(e.code()) != kPluginCrashed) throw;  // stopped, cancelled: the series'
    // The child died: the parses it answered keep their outcomes, the next one has the crash.
    std::string_view sent(received);
    if (!sent.empty() && sent.front() == 'A') sent.remove_prefix(1);
    bool whole = false;
    std::vector<ParseOutcome> out = outcomes_of(parser, requests, sent, whole);
    if (out.size() < requests.size() && (out.empty() || out.back().error == nullptr))
      out.push_back(ParseOutcome{{}, std::current_exception()});
    return out;
  }
  if (!bytes) return one_by_one();  // no child could be started: in process (isolation.hpp)
  bool whole = false;
  std::vector<ParseOutcome> out = outcomes_of(parser, requests, *bytes, whole);
  if (!whole) {  // not a series: the parse after the last whole frame has the malformed answer
    // (a series ended by a failure is whole, so here every outcome is a result; bytes past all
    // of them make the last one the malformed answer's)
    if (out.size() == requests.size()) out.pop_back();
    out.push_back(ParseOutcome{
        {},
        std::make_exception_ptr(sdk::Error(kPluginCrashed, parser.id().label() +
                                                               ": parse: its process sent a "
                                                               "malformed answer"))});
  }
  return out;
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
