#pragma once
/// @file session_extension.hpp
/// The one way into a session (docs/architecture.md §3 "Session extensions"). A module above the
/// kernel (naturalization, a front end, DDS publishing) is a SessionExtension: its attach() adds
/// ops (Session::set_op, to add or wrap one) and subscribes to the session's typed events
/// (Session::on<Event>). The session keeps its extensions and attaches them again, in the same
/// order, whenever it moves to another runtime (Session::rebind). The kernel names no extension
/// and reserves no op name for one: the app layer decides which extensions a session gets
/// (apps/wiring). A module may define events of its own (naturalization: RulesDefined) and emit
/// them through the session; subscribers find them by type.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <typeindex>
#include <utility>
#include <vector>

#include "flipper/kernel/query_service.hpp"
#include "flipper/sdk/execution.hpp"
#include "flipper/sdk/grammar.hpp"
#include "flipper/sdk/world.hpp"
#include "flipper/toolkit/json/json_writer.hpp"

namespace flipper::kernel {

class Session;

class SessionExtension {
 public:
  virtual ~SessionExtension() = default;
  /// Adds the module's ops and subscriptions to `session`; called on install and after every
  /// rebind (the session's op table and subscriptions are new then).
  virtual void attach(Session& session) = 0;
};

/// An extension from a function (a front end's few subscriptions, tests).
std::shared_ptr<SessionExtension> make_extension(std::function<void(Session&)> attach);

// ---- the kernel's events (payloads are valid during the call only) ----

/// A query (typed or protocol) begins, before its input is parsed. A throw refuses the query.
struct QueryBegins {
  Session& session;
  const std::string& text;
};
/// A query was answered (the session's last query now).
struct QueryAnswered {
  Session& session;
  const QueryResult& result;
};
/// The query op writes its answer: after "total" and "ms", before the world version, a subscriber
/// may add members of its own (docs/protocol.md § "Repairs" is one). A throw refuses the query
/// (the session's last query stays the one before).
struct QueryWriting {
  Session& session;
  const nlohmann::json& request;
  const QueryResult& result;
  toolkit::json::JsonWriter& answer;
};
/// The user changed (set_user, the `user` op).
struct UserChanged {
  Session& session;
  const std::string& user;
};
/// A parse asks which rules `user` may use: a subscriber sets `filter` (unset: every rule).
struct VisibilityAsked {
  const std::string& user;
  std::function<bool(const sdk::Rule&)>& filter;
};
/// An accept, after the scorer learned and the use counters counted, before the world changes.
/// A throw undoes the accept (scorer state, counters); the error is the answer.
struct Accepting {
  Session& session;
  const LastQuery& query;
  std::size_t rank;
  const ShownCandidate& candidate;
  const sdk::Outcome& outcome;
  const std::string& user;
};
/// A plan was accepted and committed; what a subscriber throws is logged (the accept stands).
struct PlanAccepted {
  static constexpr const char* kContained = "accepted-plan observer";
  const sdk::WorldState& before;  ///< the world the candidate was executed on
  const sdk::Outcome& outcome;    ///< its trace and final world
  const std::string& formula;     ///< the candidate in canonical core-language text
  const std::string& user;
  std::uint64_t sequence = 0;  ///< 1, 2, ... per session
};
/// The world was replaced (a `world` request, an undo): earlier plans no longer apply.
struct WorldReplaced {
  static constexpr const char* kContained = "world observer";
  Session& session;
};
/// A protocol request was answered after its op ran: the op and the error code of a refusal
/// (empty when the answer is ok). A subscriber's failure is logged (the answer stands).
struct RequestAnswered {
  static constexpr const char* kContained = "answer observer";
  const std::string& op;
  const std::string& code;
};
/// Session::activate: a request of this session comes next (sessions sharing extensions).
struct Activated {
  const Session& session;
};

/// Typed subscriptions: handlers by event type, called in subscription order.
class EventBus {
 public:
  template <class Event>
  void on(std::function<void(const Event&)> handler) {
    handlers_[typeid(Event)].push_back(
        [h = std::move(handler)](const void* e) { h(*static_cast<const Event*>(e)); });
  }
  template <class Event>
  bool has() const {
    return handlers_.count(typeid(Event)) != 0;
  }
  /// Calls every handler of the event; a throw stops and propagates, except for events that
  /// name their handlers in kContained (each handler's error is logged).
  template <class Event>
  void emit(const Event& event) const {
    auto it = handlers_.find(typeid(Event));
    if (it == handlers_.end()) return;
    for (const auto& h : it->second) {
      if constexpr (requires { Event::kContained; }) {
        try {
          h(&event);
        } catch (const std::exception& e) {
          std::cerr << "flipper: " << Event::kContained << " failed: " << e.what() << "\n";
        }
      } else {
        h(&event);
      }
    }
  }
  void clear() { handlers_.clear(); }

 private:
  std::map<std::type_index, std::vector<std::function<void(const void*)>>> handlers_;
};

}  // namespace flipper::kernel
