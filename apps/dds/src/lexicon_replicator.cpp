#include "flipper/dds/lexicon_replicator.hpp"

#include <algorithm>
#include <ctime>
#include <nlohmann/json.hpp>
#include <ostream>
#include <set>

#include "flipper/kernel/runtime.hpp"
#include "flipper/msg/LexiconEvent.h"
#include "flipper/naturalization/config_keys.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::dds {
namespace {

using kernel::Json;

std::string text(const char* s) {
  return s != nullptr ? s : "";
}

LexiconEvent from_sample(const flipper_msg_dds__LexiconEvent_& s) {
  LexiconEvent e;
  e.site = text(s.site_);
  e.version = s.version_;
  e.kind = text(s.kind_);
  e.lamport = s.lamport_;
  e.time = s.time_;
  e.author = text(s.author_);
  e.head = text(s.head_);
  for (uint32_t i = 0; i < s.body_._length; ++i) e.body.push_back(text(s.body_._buffer[i]));
  for (uint32_t i = 0; i < s.ranks_._length; ++i) e.ranks.push_back(s.ranks_._buffer[i]);
  e.world = text(s.world_);
  for (uint32_t i = 0; i < s.rules_._length; ++i) e.rules.push_back(text(s.rules_._buffer[i]));
  e.target_site = text(s.target_site_);
  e.target_version = s.target_version_;
  e.target_rule = text(s.target_rule_);
  e.certificate = text(s.certificate_);
  e.signature.assign(reinterpret_cast<const char*>(s.signature_._buffer), s.signature_._length);
  return e;
}

char* c(const std::string& s) {
  return const_cast<char*>(s.c_str());
}

dds_sequence_string strings(std::vector<char*>& holder, const std::vector<std::string>& v) {
  holder.clear();
  for (const auto& s : v) holder.push_back(c(s));
  dds_sequence_string seq{};
  seq._length = seq._maximum = static_cast<uint32_t>(holder.size());
  seq._buffer = holder.data();
  seq._release = false;
  return seq;
}

const std::set<std::string> kLive = {"applied"};

}  // namespace

std::string rule_description(const sdk::Rule& rule) {
  return naturalization::rule_shape(rule) + " => " + sdk::render(rule.sem);
}

std::shared_ptr<LexiconReplicator> LexiconReplicator::start(
    std::shared_ptr<Participant> participant, const wiring::SessionHost& host, std::ostream& log,
    const std::optional<Keystore>& keystore) {
  std::shared_ptr<LexiconReplicator> r(
      new LexiconReplicator(std::move(participant), host, log, keystore));
  r->thread_ = std::thread([raw = r.get()] { raw->loop(); });
  r->publisher_ = std::thread([raw = r.get()] { raw->publish_loop(); });
  return r;
}

LexiconReplicator::LexiconReplicator(std::shared_ptr<Participant> participant,
                                     const wiring::SessionHost& host, std::ostream& log,
                                     const std::optional<Keystore>& keystore)
    : participant_(std::move(participant)),
      host_(host),
      log_(log),
      site_(host.runtime->config.get(naturalization::keys::kSite)),
      executor_(host.runtime->planner,
                kernel::SessionOptions::from_config(host.runtime->config).limits) {
  if (keystore) {
    signer_ = std::make_unique<EventSigner>(*keystore, site_);
    verifier_ = std::make_unique<EventVerifier>(*keystore);
  }
  log_db_ = std::make_unique<ReplicationLog>(host_.naturalizer->store().path());
  Qos qos;
  history_qos(qos);
  // This site's own events never come back to it through its reader.
  dds_qset_ignorelocal(qos.q, DDS_IGNORELOCAL_PARTICIPANT);
  auto& p = *participant_;
  const dds_entity_t topic = p.topic(&flipper_msg_dds__LexiconEvent__desc, kLexiconTopic);
  writer_ =
      check(dds_create_writer(p.handle(), topic, qos.q, nullptr), "creating the lexicon writer");
  reader_ =
      check(dds_create_reader(p.handle(), topic, qos.q, nullptr), "creating the lexicon reader");
  waitset_ = check(dds_create_waitset(p.handle()), "creating a waitset");
  check(dds_set_status_mask(reader_, DDS_DATA_AVAILABLE_STATUS), "reader status mask");
  check(dds_waitset_attach(waitset_, reader_, reader_), "attaching the lexicon reader");
  std::lock_guard lock(mutex_);
  recover();
  // Catch-up for late and restarted sites: the whole log, every site's events as they were
  // (this site's own, made before security was on, signed now).
  std::vector<LogRow> rows;
  for (const auto& [key, row] : log_db_->rows()) rows.push_back(row);
  for (auto& row : rows) {
    if (signer_ && row.event.site == site_ && row.event.signature.empty()) {
      signer_->sign(row.event);
      log_db_->put(row);
    }
    publish(row.event);
  }
  log_ << "flipper: lexicon replication: site '" << site_ << "', " << log_db_->rows().size()
       << " events in the log, topic " << kLexiconTopic
       << (signer_ ? ", events signed and checked (DDS Security)"
                   : ", every participant on the domain trusted (DDS Security off)")
       << std::endl;
}

LexiconReplicator::~LexiconReplicator() {
  stop_.store(true);
  outbox_ready_.notify_one();
  if (thread_.joinable()) thread_.join();
  if (publisher_.joinable()) publisher_.join();
  for (dds_entity_t e : {waitset_, reader_, writer_})
    if (e > 0) dds_delete(e);
}

void LexiconReplicator::recover() {
  // Decisions made while this site was down: approved definitions are claimed before the loop
  // below could take them for definitions made here before replication.
  check_moderation();
  auto& store = host_.naturalizer->store();
  std::set<std::int64_t> claimed;
  for (const auto& [key, row] : log_db_->rows())
    if (row.definition != 0) claimed.insert(row.definition);
  const auto definitions = store.definitions();
  std::set<std::string> followed;
  for (const auto& [id, h] : log_db_->held()) followed.insert(id);
  const auto held = store.held();
  // Killed between the store's commit and the log's: the definition is there, unclaimed (or
  // held for this site's moderator, unfollowed).
  std::vector<LogRow> redo;
  for (const auto& [key, row] : log_db_->rows()) {
    if (row.status != "applying") continue;
    LogRow fixed = row;
    for (const auto& h : held)
      if (!followed.count(h.id) && h.definition.via == "replicate" &&
          h.definition.head == row.event.head && h.definition.body == row.event.body &&
          h.definition.author == row.event.author) {
        fixed.status = "held";
        log_db_->put_held({h.id, row.event, false});
        followed.insert(h.id);
        break;
      }
    if (fixed.status == "held") {
      log_db_->put(fixed);
      continue;
    }
    for (const auto& d : definitions)
      if (!claimed.count(d.id) && d.head == row.event.head && d.body == row.event.body &&
          d.author == row.event.author) {
        fixed.definition = d.id;
        fixed.local_rules = rules_of(d.id);
        fixed.status = "applied";
        claimed.insert(d.id);
        break;
      }
    if (fixed.status == "applied")
      log_db_->put(fixed);
    else
      redo.push_back(fixed);
  }
  for (auto& row : redo) apply(row);
  // Definitions made here before replication was on (or killed before their log row): ours.
  for (const auto& d : definitions) {
    if (claimed.count(d.id)) continue;
    LogRow row;
    row.event = next_local_event("define");
    row.event.author = d.author;
    row.event.head = d.head;
    row.event.body = d.body;
    row.event.time = d.time;
    row.definition = d.id;
    row.local_rules = rules_of(d.id);
    for (const auto& id : row.local_rules)
      if (auto rule = host_.naturalizer->find_rule(id))
        row.event.rules.push_back(rule_description(*rule));
    row.status = "applied";
    if (signer_) signer_->sign(row.event);
    log_db_->put(row);
  }
  retry_pending();
}

std::vector<std::string> LexiconReplicator::rules_of(std::int64_t definition) const {
  std::vector<std::string> ids;
  for (const auto& r : host_.naturalizer->store().rules(true))
    if (r.definition == definition) ids.push_back(r.id);
  return ids;
}

LexiconEvent LexiconReplicator::next_local_event(const std::string& kind) const {
  LexiconEvent e;
  e.site = site_;
  e.version = log_db_->max_version(site_) + 1;
  e.kind = kind;
  e.lamport = log_db_->max_lamport() + 1;
  e.time = static_cast<std::int64_t>(std::time(nullptr));
  return e;
}

void LexiconReplicator::publish(const LexiconEvent& e) {
  {
    std::lock_guard lock(outbox_mutex_);
    outbox_.push_back(e);
  }
  outbox_ready_.notify_one();
}

// The outbox's thread: dds_write of a reliable keep-all writer blocks while readers that died
// (and still count until their lease ends) hold back acknowledgements; it blocks here, never
// in a session's request or the reader thread. An event that times out is tried again.
void LexiconReplicator::publish_loop() {
  for (;;) {
    std::unique_lock lock(outbox_mutex_);
    outbox_ready_.wait(lock, [&] { return stop_.load() || !outbox_.empty(); });
    if (outbox_.empty()) return;  // stopping, everything handed to DDS
    const LexiconEvent e = outbox_.front();
    lock.unlock();
    const dds_return_t rc = write_now(e);
    if (rc == DDS_RETCODE_TIMEOUT && !stop_.load()) continue;
    if (rc < 0)
      log_ << "flipper: lexicon replication: publishing " << e.identity()
           << " failed: " << dds_strretcode(rc) << std::endl;
    lock.lock();
    outbox_.pop_front();
  }
}

dds_return_t LexiconReplicator::write_now(const LexiconEvent& e) {
  std::vector<char*> body, rules;
  flipper_msg_dds__LexiconEvent_ s{};
  s.site_ = c(e.site);
  s.version_ = e.version;
  s.kind_ = c(e.kind);
  s.lamport_ = e.lamport;
  s.time_ = e.time;
  s.author_ = c(e.author);
  s.head_ = c(e.head);
  s.body_ = strings(body, e.body);
  std::vector<int32_t> ranks(e.ranks.begin(), e.ranks.end());
  s.ranks_._length = s.ranks_._maximum = static_cast<uint32_t>(ranks.size());
  s.ranks_._buffer = ranks.data();
  s.ranks_._release = false;
  s.world_ = c(e.world);
  s.rules_ = strings(rules, e.rules);
  s.target_site_ = c(e.target_site);
  s.target_version_ = e.target_version;
  s.target_rule_ = c(e.target_rule);
  s.certificate_ = c(e.certificate);
  s.signature_._length = s.signature_._maximum = static_cast<uint32_t>(e.signature.size());
  s.signature_._buffer = reinterpret_cast<uint8_t*>(const_cast<char*>(e.signature.data()));
  s.signature_._release = false;
  return dds_write(writer_, &s);
}

void LexiconReplicator::loop() {
  while (!stop_.load()) {
    dds_attach_t triggered = 0;
    if (dds_waitset_wait(waitset_, &triggered, 1, DDS_MSECS(100)) < 0) return;
    take_available();
    while (sessions_waiting_.load() > 0) std::this_thread::yield();
    std::lock_guard lock(mutex_);
    if (log_db_->held().empty()) continue;
    try {
      check_moderation();
    } catch (const std::exception& ex) {
      log_ << "flipper: lexicon replication: following the moderation queue: " << ex.what()
           << std::endl;
    }
  }
}

void LexiconReplicator::take_available() {
  constexpr int kBatch = 32;
  void* samples[kBatch] = {};
  dds_sample_info_t infos[kBatch];
  for (;;) {
    const dds_return_t n = dds_take(reader_, samples, infos, kBatch, kBatch);
    if (n <= 0) return;
    std::vector<LexiconEvent> events;
    for (dds_return_t i = 0; i < n; ++i)
      if (infos[i].valid_data)
        events.push_back(from_sample(*static_cast<flipper_msg_dds__LexiconEvent_*>(samples[i])));
    dds_return_loan(reader_, samples, n);
    for (const auto& e : events) {
      if (auto why = malformed(e)) {
        ++dropped_;
        log_ << "flipper: lexicon replication: dropped a malformed event from site '"
             << e.site.substr(0, 64) << "': " << *why << std::endl;
        continue;
      }
      // Not logged: the authentic event of the same (site, version) must still get in.
      if (auto why = verifier_ ? verifier_->why_not(e) : std::nullopt) {
        ++refused_;
        log_ << "flipper: lexicon replication: refused event " << e.identity().substr(0, 80) << ": "
             << *why << std::endl;
        continue;
      }
      // Sessions first: a user's request never waits behind a whole catch-up.
      while (sessions_waiting_.load() > 0) std::this_thread::yield();
      std::lock_guard lock(mutex_);
      try {
        receive(e);
      } catch (const std::exception& ex) {
        log_ << "flipper: lexicon replication: event " << e.identity()
             << " not applied: " << ex.what() << std::endl;
      }
    }
  }
}

void LexiconReplicator::receive(const LexiconEvent& e) {
  if (log_db_->find({e.site, e.version}) != nullptr) return;  // replay: already here
  LogRow row;
  row.event = e;
  const bool done = apply(row);
  // Logged (applied, pending, refused or superseded): relayed, so this site's writer holds every
  // event it knows and a site that joins later catches up from it, whoever is down.
  publish(e);
  if (done) {
    ++applied_;
    retry_pending();
  }
}

bool LexiconReplicator::apply(LogRow row) {
  const bool done = row.event.kind == "define" ? apply_define(row) : apply_delete(row);
  if (!done) {
    row.status = "pending";
    log_db_->put(row);
  }
  return done;
}

bool LexiconReplicator::dominated(const LexiconEvent& e) const {
  for (const auto& [key, other] : log_db_->rows())
    if (other.event.kind == "define" && other.event.head == e.head && other.event.site != e.site &&
        other.status != "refused" && other.status != "held" && other.status != "rejected" &&
        other.event.wins_over(e))
      return true;
  return false;
}

bool LexiconReplicator::apply_define(LogRow& row) {
  if (dominated(row.event)) {
    row.status = "superseded";
    log_db_->put(row);
    log_ << "flipper: lexicon replication: " << row.event.identity() << " ('" << row.event.head
         << "') superseded by a later definition of the same head from another site" << std::endl;
    return true;
  }
  row.status = "applying";  // durable before the store commits: recover() finds a kill here
  log_db_->put(row);
  naturalization::DefineRequest req;
  req.user = row.event.author;
  req.head = row.event.head;
  req.body = row.event.body;
  req.body_ranks = row.event.ranks;
  req.via = "replicate";  // its history entry says so; its site checked its conflicts
  std::optional<sdk::WorldState> world;
  if (!row.event.world.empty()) {
    try {
      world = host_.runtime->world.call(
          "load", [&](const sdk::World& w) { return w.load(row.event.world, "."); });
      req.before = &*world;
      req.exec = &executor_;
    } catch (const std::exception& ex) {
      log_ << "flipper: lexicon replication: " << row.event.identity()
           << ": its world does not load here (" << ex.what() << "); induced without it"
           << std::endl;
    }
  }
  try {
    const naturalization::DefineOutcome out = host_.naturalizer->define(req);
    if (!out.held.empty()) {  // lexicon.moderation = hold_new: for this site's researcher
      row.status = "held";
      log_db_->put(row);
      log_db_->put_held({out.held, row.event, false});
      log_ << "flipper: lexicon replication: " << row.event.identity() << " ('" << row.event.head
           << "' by " << row.event.author << ") held for this site's moderator as " << out.held
           << std::endl;
      return true;
    }
    row.definition = out.definition;
    row.local_rules.clear();
    for (const auto& r : out.rules) row.local_rules.push_back(r->id);
  } catch (const sdk::Error& ex) {
    if (ex.code() == "body_unparsable") return false;  // waits for the rules it uses
    if (ex.code() == "bad_lexicon") throw;
    row.status = "refused";
    log_db_->put(row);
    log_ << "flipper: lexicon replication: refused " << row.event.identity() << ": " << ex.code()
         << ": " << ex.what() << std::endl;
    return true;
  }
  row.status = "applied";
  log_db_->put(row);
  settle(row.event.head);
  return true;
}

bool LexiconReplicator::apply_delete(LogRow& row) {
  const LexiconEvent& e = row.event;
  if (e.site != e.target_site) {
    row.status = "refused";
    log_db_->put(row);
    log_ << "flipper: lexicon replication: refused deletion " << e.identity() << ": site '"
         << e.site << "' may not delete definition " << e.target_site << "#" << e.target_version
         << " (only its author's site may)" << std::endl;
    return true;
  }
  const LogRow* target = log_db_->find({e.target_site, e.target_version});
  // A held target waits for this site's moderator: approved, its rules go; rejected, none serve.
  if (target == nullptr || target->status == "pending" || target->status == "applying" ||
      target->status == "held")
    return false;
  for (const auto& id : target->local_rules) {
    auto rule = host_.naturalizer->find_rule(id);
    if (rule && (e.target_rule.empty() || rule_description(*rule) == e.target_rule))
      host_.naturalizer->delete_rule(rule->author, id);
  }
  row.status = "applied";
  log_db_->put(row);
  return true;
}

void LexiconReplicator::retry_pending() {
  for (bool progress = true; progress;) {
    progress = false;
    std::vector<LogRow> pending;
    for (const auto& [key, row] : log_db_->rows())
      if (row.status == "pending") pending.push_back(row);
    for (auto& row : pending)
      if (apply(row)) {
        ++applied_;
        progress = true;
      }
  }
}

void LexiconReplicator::retire(LogRow& row) {
  for (const auto& id : row.local_rules)
    if (auto rule = host_.naturalizer->find_rule(id))
      host_.naturalizer->delete_rule(rule->author, id);
  row.status = "superseded";
  log_db_->put(row);
  log_ << "flipper: lexicon replication: " << row.event.identity() << " ('" << row.event.head
       << "') superseded by a later definition of the same head from another site" << std::endl;
}

void LexiconReplicator::settle(const std::string& head) {
  std::vector<LogRow> losers;
  for (const auto& [key, row] : log_db_->rows())
    if (row.event.kind == "define" && row.event.head == head && row.status == "applied" &&
        dominated(row.event))
      losers.push_back(row);
  for (auto& row : losers) retire(row);
}

std::unique_lock<std::recursive_mutex> LexiconReplicator::session_lock() {
  sessions_waiting_.fetch_add(1);
  std::unique_lock lock(mutex_);
  sessions_waiting_.fetch_sub(1);
  return lock;
}

void LexiconReplicator::attach(kernel::Session& session) {
  std::weak_ptr<LexiconReplicator> weak = weak_from_this();
  for (const auto& name : session.op_names()) {
    kernel::Session::OpHandler inner = *session.find_op(name);
    kernel::Session::OpHandler wrapped;
    if (name == "delete_rule")
      wrapped = [weak, inner](kernel::Session& s, const Json& r, toolkit::json::JsonWriter& a) {
        auto self = weak.lock();
        if (!self) return inner(s, r, a);
        const auto lock = self->session_lock();
        self->delete_op(inner, s, r, a);
      };
    else
      wrapped = [weak, inner](kernel::Session& s, const Json& r, toolkit::json::JsonWriter& a) {
        auto self = weak.lock();
        if (!self) return inner(s, r, a);
        const auto lock = self->session_lock();
        inner(s, r, a);
      };
    session.set_op(name, std::move(wrapped));
  }
  session.on<naturalization::RulesDefined>([weak](const naturalization::RulesDefined& e) {
    // A dry run or a preview stored nothing to share; a held definition (lexicon.moderation) is
    // followed until its researcher decides, and published only when approved.
    auto self = weak.lock();
    if (!self) return;
    if (e.outcome.stored)
      self->defined(e);
    else if (!e.outcome.held.empty())
      self->held_here(e);
  });
}

void LexiconReplicator::defined(const naturalization::RulesDefined& e) {
  const auto lock = session_lock();  // already held when the define came as an op
  LogRow row;
  row.event = next_local_event("define");
  row.event.author = e.session.user();
  row.event.head = e.call.head;
  row.event.body = e.call.body;
  row.event.ranks = e.call.ranks;
  row.event.world = e.session.world_json(e.session.world()).dump();  // a define keeps the world
  const auto definitions = host_.naturalizer->store().definitions();
  row.definition = definitions.empty() ? 0 : definitions.back().id;
  for (const auto& rule : e.outcome.rules) {
    row.local_rules.push_back(rule->id);
    if (auto live = host_.naturalizer->find_rule(rule->id))
      row.event.rules.push_back(rule_description(*live));
  }
  row.status = "applied";
  if (signer_) signer_->sign(row.event);
  log_db_->put(row);
  // A definition of the same head from another site may have arrived before this one: this one
  // saw it, so it is later and wins; the other site's rules go here too, as they do elsewhere.
  settle(row.event.head);
  publish(row.event);
}

void LexiconReplicator::delete_op(const kernel::Session::OpHandler& inner, kernel::Session& s,
                                  const Json& req, toolkit::json::JsonWriter& a) {
  const auto rule_field = req.find("rule");
  if (rule_field == req.end() || !rule_field->is_string()) return inner(s, req, a);
  const std::string id = rule_field->get<std::string>();
  const LogRow* origin = nullptr;
  for (const auto& [key, row] : log_db_->rows())
    if (row.event.kind == "define" &&
        std::find(row.local_rules.begin(), row.local_rules.end(), id) != row.local_rules.end())
      origin = &row;
  const auto rule = host_.naturalizer->find_rule(id);
  if (origin != nullptr && rule && origin->event.site != site_) {
    log_ << "flipper: lexicon replication: refused deleting " << id << " at site '" << site_
         << "': it comes from site '" << origin->event.site << "'" << std::endl;
    throw sdk::Error(naturalization::naturalize_codes::kForbidden,
                     "rule " + id + " was defined at site '" + origin->event.site +
                         "'; only that site may delete it");
  }
  const std::string description = rule ? rule_description(*rule) : std::string();
  const LogRow* target = origin;
  LexiconEvent e;
  if (target != nullptr) {
    e = next_local_event("delete");
    e.target_site = target->event.site;
    e.target_version = target->event.version;
  }
  inner(s, req, a);  // refuses (forbidden, not_found) before anything is published
  if (target != nullptr) {
    e.author = s.user();
    e.target_rule = description;
    if (signer_) signer_->sign(e);
    LogRow row;
    row.event = e;
    row.status = "applied";
    log_db_->put(row);
    publish(e);
  }
}

}  // namespace flipper::dds
