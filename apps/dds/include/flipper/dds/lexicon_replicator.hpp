#pragma once
/// @file lexicon_replicator.hpp
/// `lexicon.replication: dds`: one lexicon across sites. Every definition and deletion made at
/// this site (lexicon.site) is published on rt/flipper/lexicon (reliable, TRANSIENT_LOCAL,
/// keep-all) as a LexiconEvent with its identity (site, version), author and a Lamport clock;
/// every event from another site is applied to this site's own store:
///   - definitions are replayed through induction (as `flipper lexicon import` does), in the
///     world they were made in when the event carries it (so generalization runs too);
///   - idempotent: an event whose (site, version) is in the replication log is skipped, and a
///     kill between the store's commit and the log's is recovered at start-up (replication_log);
///   - catch-up from any live site: at start-up every site re-publishes its whole log, and it
///     relays every event it receives (own writer, TRANSIENT_LOCAL, keep-all), so every live
///     site's writer holds every event that site knows and a late or restarted site gets them
///     all from whichever sites are up, the author down or not;
///   - identity (DDS Security on, keystore given): this site signs its events; an event is
///     accepted only when signed by the site it names (event_signature.hpp), otherwise dropped
///     unlogged. Security off: any participant on the domain is trusted;
///   - deletions: only the author's site may delete a definition's rules (a local delete_rule of
///     another site's rule is refused with `forbidden`; a received deletion from another site is
///     refused); both are logged;
///   - conflicts: a definition is retired (its rules deleted here, status superseded) as soon as
///     a definition of the same head from ANOTHER site with a larger (lamport, site) is known.
///     The live set is therefore a function of the events alone: every site converges to it.
///   - moderation (lexicon.moderation = hold_new; docs/ros2.md "Moderation across sites"): a
///     definition held here is not published; when this site's researcher approves it (`flipper
///     lexicon approve`, any process on the store) it is published as this site's event, made
///     then (its author and world kept, signed by this site; the approval, naming the moderator,
///     is in this site's history). A definition from another site is held here too, for this
///     site's researcher: approved, it serves here (not published again: it is the other site's
///     event); rejected, it never serves here. Rejections are local history only. Held and
///     rejected definitions take no part in "newest wins" here, and a deletion of a held one
///     waits for the researcher's decision. Decisions are seen by polling the store (each
///     wake-up of the reader thread, at most 100 ms apart, only while something is held).
/// A definition whose body does not parse yet (it uses a rule still on its way) waits (pending)
/// and is retried after each applied event; so do deletions that arrive before their definition.
/// Malformed samples are logged and dropped.
///
/// Thread model: a reader thread applies events under one mutex; attach() wraps every op of a
/// session in the same mutex, so sessions and replication never touch the lexicon at once. The
/// reader takes the mutex per event and only when no session waits for it, so a request waits
/// for at most one event's application, never for a whole catch-up.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "flipper/dds/event_signature.hpp"
#include "flipper/dds/keystore.hpp"
#include "flipper/dds/lexicon_event.hpp"
#include "flipper/dds/participant.hpp"
#include "flipper/dds/replication_log.hpp"
#include "flipper/kernel/executor.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/wiring/session_factory.hpp"

namespace flipper::dds {

inline constexpr const char* kLexiconTopic = "rt/flipper/lexicon";

class LexiconReplicator : public std::enable_shared_from_this<LexiconReplicator> {
 public:
  /// Recovers the log, re-publishes the history and starts the reader thread.
  /// `keystore`: DDS Security on (lexicon.site must be an identity of it).
  static std::shared_ptr<LexiconReplicator> start(std::shared_ptr<Participant> participant,
                                                  const wiring::SessionHost& host,
                                                  std::ostream& log,
                                                  const std::optional<Keystore>& keystore = {});
  ~LexiconReplicator();
  LexiconReplicator(const LexiconReplicator&) = delete;
  LexiconReplicator& operator=(const LexiconReplicator&) = delete;

  /// Wraps the session's ops: every op under the replication mutex; delete_rule refuses other
  /// sites' rules and publishes the deletion. Subscribes to the session's RulesDefined: each
  /// definition is logged and published.
  void attach(kernel::Session& session);
  const std::string& site() const { return site_; }
  /// Received events applied, and samples dropped as malformed (for tests and benchmarks).
  std::uint64_t applied() const { return applied_.load(); }
  std::uint64_t dropped() const { return dropped_.load(); }
  /// Well-formed events refused as not authentic (DDS Security on).
  std::uint64_t refused() const { return refused_.load(); }

 private:
  LexiconReplicator(std::shared_ptr<Participant> participant, const wiring::SessionHost& host,
                    std::ostream& log, const std::optional<Keystore>& keystore);
  void recover();
  void loop();
  void take_available();
  void receive(const LexiconEvent& e);
  bool apply(LogRow row);  // false: left pending
  bool apply_define(LogRow& row);
  bool apply_delete(LogRow& row);
  void retry_pending();
  /// Follows the moderator's decisions on held definitions (approved or rejected since the last
  /// look): publishes this site's approved ones, applies or rejects other sites' ones.
  void check_moderation();
  void held_here(const naturalization::RulesDefined& e);
  /// The local rule ids of definition `id` in the store.
  std::vector<std::string> rules_of(std::int64_t definition) const;
  void settle(const std::string& head);
  bool dominated(const LexiconEvent& e) const;
  void retire(LogRow& row);
  void publish(const LexiconEvent& e);  // queued for publish_loop
  void publish_loop();
  dds_return_t write_now(const LexiconEvent& e);
  LexiconEvent next_local_event(const std::string& kind) const;
  /// The mutex for a session's op; the reader thread lets waiting sessions go first.
  std::unique_lock<std::recursive_mutex> session_lock();
  void defined(const naturalization::RulesDefined& e);
  void delete_op(const kernel::Session::OpHandler& inner, kernel::Session& s,
                 const kernel::Json& req, toolkit::json::JsonWriter& answer);

  std::shared_ptr<Participant> participant_;
  wiring::SessionHost host_;
  std::ostream& log_;
  std::string site_;
  kernel::Executor executor_;
  std::unique_ptr<ReplicationLog> log_db_;
  std::recursive_mutex mutex_;
  std::atomic<int> sessions_waiting_{0};
  dds_entity_t reader_ = 0;
  dds_entity_t writer_ = 0;
  dds_entity_t waitset_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> applied_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> refused_{0};
  std::unique_ptr<EventSigner> signer_;  // DDS Security on
  std::unique_ptr<EventVerifier> verifier_;
  std::thread thread_;
  std::mutex outbox_mutex_;
  std::condition_variable outbox_ready_;
  std::deque<LexiconEvent> outbox_;
  std::thread publisher_;
};

/// "lhs -> rhs => semantics": how events name a rule across sites (never by local id).
std::string rule_description(const sdk::Rule& rule);

}  // namespace flipper::dds
