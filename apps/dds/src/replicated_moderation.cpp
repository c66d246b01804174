// Moderation across sites (docs/ros2.md "Moderation across sites"; lexicon_replicator.hpp): the
// replicator follows this site's moderation queue (lexicon.moderation = hold_new). A definition
// held here waits in the store's queue and, with what replication needs to publish it (its
// world), in the replication log's `dds_held` table; the researcher's decision is read back from
// the store's history, whichever process made it.
#include <ostream>
#include <set>

#include "flipper/dds/lexicon_replicator.hpp"
#include "flipper/naturalization/lexicon_history.hpp"
#include "flipper/naturalization/naturalizer.hpp"

namespace flipper::dds {

void LexiconReplicator::held_here(const naturalization::RulesDefined& e) {
  const auto lock = session_lock();
  HeldRow row;
  row.held = e.outcome.held;
  row.own = true;
  row.event.site = site_;
  row.event.kind = "define";
  row.event.author = e.session.user();
  row.event.head = e.call.head;
  row.event.body = e.call.body;
  row.event.ranks = e.call.ranks;
  row.event.world = e.session.world_json(e.session.world()).dump();
  log_db_->put_held(row);
}

void LexiconReplicator::check_moderation() {
  if (log_db_->held().empty()) return;
  auto& store = host_.naturalizer->store();
  std::set<std::string> still;
  for (const auto& h : store.held()) still.insert(h.id);
  std::vector<HeldRow> decided;
  for (const auto& [id, row] : log_db_->held())
    if (!still.count(id)) decided.push_back(row);
  if (decided.empty()) return;
  host_.naturalizer->refresh();  // the approved rules, whichever process approved them
  const auto history = store.history();
  for (const auto& h : decided) {
    // The store's history says what happened to it: `approve` (then the definition's own
    // entries) or `reject`, each with the held id in its note (lexicon/moderation.cpp).
    const naturalization::HistoryEntry* approval = nullptr;
    std::int64_t definition = 0;
    for (const auto& entry : history) {
      if (approval == nullptr && entry.action == naturalization::history_action::kApprove &&
          entry.note == h.held)
        approval = &entry;
      else if (approval != nullptr && entry.seq > approval->seq && entry.definition != 0 &&
               entry.head == h.event.head) {
        definition = entry.definition;
        break;
      }
    }
    LogRow* origin = nullptr;
    LogRow row;
    if (!h.own) {
      if (const LogRow* r = log_db_->find({h.event.site, h.event.version})) row = *r;
      origin = &row;
    }
    if (definition == 0) {  // rejected: nothing serves here, nothing is published
      if (origin != nullptr) {
        row.status = "rejected";
        log_db_->put(row);
      }
      log_db_->drop_held(h.held);
      log_ << "flipper: lexicon replication: held " << h.held << " ('" << h.event.head
           << "') rejected here" << (h.own ? "; not published" : "") << std::endl;
      continue;
    }
    if (origin == nullptr) {  // this site's own: published now, as a definition made now
      LexiconEvent e = next_local_event("define");
      row.event = h.event;
      row.event.version = e.version;
      row.event.lamport = e.lamport;
      row.event.time = e.time;
    }
    row.definition = definition;
    row.local_rules = rules_of(definition);
    if (origin == nullptr)
      for (const auto& id : row.local_rules)
        if (auto rule = host_.naturalizer->find_rule(id))
          row.event.rules.push_back(rule_description(*rule));
    row.status = "applied";
    if (origin == nullptr && signer_) signer_->sign(row.event);
    log_db_->put(row);
    log_db_->drop_held(h.held);
    log_ << "flipper: lexicon replication: held " << h.held << " ('" << h.event.head << "' by "
         << h.event.author << ") approved by " << approval->author << "; "
         << (origin == nullptr ? "published as " + row.event.identity()
                               : "serves here (" + row.event.identity() + ")")
         << std::endl;
    settle(row.event.head);
    if (origin == nullptr) publish(row.event);
  }
  retry_pending();
}

}  // namespace flipper::dds
