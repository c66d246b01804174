#include "flipper/naturalization/naturalizer.hpp"

#include <algorithm>
#include <ctime>
#include <iostream>
#include <map>
#include <type_traits>
#include <unordered_map>

#include "flipper/kernel/plugin_checks.hpp"
#include "flipper/naturalization/generalizer.hpp"
#include "flipper/naturalization/rule_snapshot.hpp"
#include "flipper/sdk/canonical.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/grammar.hpp"

namespace flipper::naturalization {

namespace {

sdk::RuleOrigin origin_from_string(std::string_view how) {
  if (how == "simple") return sdk::RuleOrigin::simple;
  if (how == "best") return sdk::RuleOrigin::best;
  if (how == "alignment") return sdk::RuleOrigin::alignment;
  if (how == "rewriting") return sdk::RuleOrigin::rewriting;
  throw sdk::Error(lexicon_codes::kBadLexicon, "unknown rule origin '" + std::string(how) + "'");
}

/// Whether a rule of `author` serves `user` under `sharing` (induced rules only).
bool visible_author(Sharing sharing, const std::string& author, const std::string& user) {
  switch (sharing) {
    case Sharing::shared:
      return true;
    case Sharing::private_:
      return author == user;
    case Sharing::core:
      return false;
  }
  return true;
}

void warn_stderr(const std::string& message) {
  std::cerr << "flipper: warning: " << message << "\n";
}

std::string symbol_text(const sdk::Symbol& s) {
  return s.text;
}

template <class Stored>
std::string rule_shape_text(const Stored& s) {
  std::string text(s.lhs);
  text += " ->";
  for (const auto& sym : s.rhs) (text += ' ') += sym;
  return text;
}

}  // namespace

std::string rule_shape(const sdk::Rule& rule) {
  std::string key = rule.lhs + " ->";
  for (const auto& s : rule.rhs) key += " " + symbol_text(s);
  return key;
}

std::uint64_t shape_hash(const sdk::Rule& rule) {
  // The texts of rule_shape() hashed piece by piece: no string is built (start-up hashes every
  // rule). Equal shapes hash equal; a collision only costs a same_rule() comparison. FNV-1a,
  // inline, with a separator byte per symbol: a third of std::hash's cost on these short
  // texts (the value lives in memory only, never stored).
  std::uint64_t h = 0xCBF29CE484222325ULL;
  auto mix = [&h](std::string_view text) {
    for (const char c : text) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001B3ULL;
    h = (h ^ 0xFFU) * 0x100000001B3ULL;  // "a b" and "ab" differ
  };
  mix(rule.lhs);
  for (const auto& s : rule.rhs) mix(s.text);
  return h;
}

StoredRule stored_from_rule(const sdk::Rule& rule, std::int64_t definition) {
  StoredRule s;
  s.id = rule.id;
  s.lhs = rule.lhs;
  for (const auto& sym : rule.rhs) s.rhs.push_back(symbol_text(sym));
  s.semantics = sdk::render(rule.sem);
  s.author = rule.author;
  s.head = rule.head;
  s.body = rule.body;
  s.how = sdk::to_string(rule.how);
  s.created = rule.created;
  s.definition = definition;  // a new rule: no uses yet
  return s;
}

namespace {
// Templates repeat across a lexicon (one definition's rules, and users define alike); a program
// is immutable, so rules with the same template text and sorts share one (start-up reads each
// distinct template once). Per thread, bounded.
sdk::Program cached_template(std::string_view text, sdk::Sort sort,
                             const std::vector<sdk::Sort>& holes) {
  thread_local std::unordered_map<std::string, sdk::Program> cache;
  thread_local std::string key;  // reused: a lookup allocates nothing
  key.assign(text);
  key += '\0';
  key += static_cast<char>(sort);
  for (sdk::Sort h : holes) key += static_cast<char>(h);
  if (auto it = cache.find(key); it != cache.end()) return it->second;
  sdk::Program p = sdk::read_template(text, sort, holes);
  if (cache.size() >= 4096) cache.clear();
  cache.emplace(key, p);
  return p;
}

// The sort of a category's normal form (normalize + look up: several allocations), remembered
// per category text; a lexicon uses a handful. Throws like sdk::category_sort for unknown ones.
sdk::Sort cached_sort(std::string_view category) {
  thread_local std::vector<std::pair<std::string, sdk::Sort>> known;
  for (const auto& [name, sort] : known)
    if (name == category) return sort;
  const sdk::Sort sort = sdk::category_sort(sdk::normalize_category(std::string(category)));
  if (known.size() < 64) known.emplace_back(category, sort);
  return sort;
}
}  // namespace

namespace {
// Checks everything that can throw before taking anything from `s`, so a rule that does not
// load leaves its StoredRule intact for the quarantine report.
template <class Stored>
sdk::RulePtr build_rule(Stored&& s) {
  // A row whose lists do not decode, or whose right-hand side could not be a rule of the grammar
  // (nothing, or one category alone: docs/naturalization.md §4.7), is quarantined.
  if (!s.decode_error.empty())
    throw sdk::Error(lexicon_codes::kCorrupt, std::string(s.decode_error));
  if (s.rhs.empty())
    throw sdk::Error(lexicon_codes::kCorrupt,
                     "'" + rule_shape_text(s) + "' has an empty right-hand side (column 'rhs')");
  if (s.rhs.size() == 1 && !s.rhs[0].empty() && s.rhs[0][0] == '$')
    throw sdk::Error(lexicon_codes::kCorrupt,
                     "'" + rule_shape_text(s) + "' has a single category as its right-hand side");
  // Older versions induced `$Action -> $ROOT thrice`-like rules, whose hole takes a whole
  // sequence; such a rule is not read (so it is quarantined, with this message).
  static const std::string root = sdk::Grammar{}.root;
  if (s.lhs == root || std::find(s.rhs.begin(), s.rhs.end(), root) != s.rhs.end())
    throw sdk::Error(lexicon_codes::kBadLexicon,
                     "'" + rule_shape_text(s) + "' uses the grammar root " + root +
                         " as a hole (induced by an older Flipper); re-induce the store's "
                         "definitions: flipper lexicon export FILE, then flipper lexicon import "
                         "FILE into a new lexicon.path");
  // Moves out of an owned StoredRule; copies from a const one or from a view.
  constexpr bool kMove = std::is_rvalue_reference_v<Stored&&> &&
                         std::is_same_v<std::remove_cvref_t<Stored>, StoredRule>;
  // Into the rule's own field: from a view that is one copy, no temporary string moved in.
  auto take = [](auto& field, std::string& into) {
    if constexpr (kMove)
      into = std::move(field);
    else
      into.assign(field);
  };
  // Induced RHS hold plain tokens and categories only; a token never starts with '$'.
  auto is_category = [](std::string_view text) { return !text.empty() && text[0] == '$'; };
  thread_local std::vector<sdk::Sort> holes;  // reused: no allocation per rule
  holes.clear();
  for (const auto& text : s.rhs)
    if (is_category(text)) holes.push_back(cached_sort(text));
  sdk::Program sem = cached_template(s.semantics, cached_sort(s.lhs), holes);
  const sdk::RuleOrigin how = origin_from_string(s.how);
  // Nothing below throws but allocation.
  std::vector<sdk::Symbol> rhs;
  rhs.reserve(s.rhs.size());
  for (auto& text : s.rhs) {
    sdk::Symbol& symbol = rhs.emplace_back();
    symbol.type = is_category(text) ? sdk::Symbol::Type::category : sdk::Symbol::Type::token;
    take(text, symbol.text);
  }
  auto rule = std::make_shared<sdk::Rule>();
  take(s.id, rule->id);
  take(s.lhs, rule->lhs);
  rule->rhs = std::move(rhs);
  rule->sem = std::move(sem);
  rule->induced = true;
  rule->how = how;
  take(s.author, rule->author);
  take(s.head, rule->head);
  if constexpr (kMove)
    rule->body = std::move(s.body);
  else
    rule->body.assign(s.body.begin(), s.body.end());
  rule->created = s.created;
  return rule;
}
}  // namespace

sdk::RulePtr rule_from_stored(const StoredRule& s) {
  return build_rule(s);
}

sdk::RulePtr rule_from_stored(StoredRule&& s) {
  return build_rule(std::move(s));
}

sdk::RulePtr rule_from_stored(const StoredRuleView& s) {
  return build_rule(s);
}

std::optional<std::string> quarantine_reason(const StoredRule& stored) {
  try {
    (void)rule_from_stored(stored);
    return std::nullopt;
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
}

void check_head_tokens(const std::string& head) {
  for (const auto& token : sdk::tokenize(head))
    if (!token.empty() && token[0] == '$')
      throw sdk::Error(naturalize_codes::kHeadReservedToken,
                       "the head token '" + token +
                           "' starts with '$', which marks grammar categories in rules; a head is "
                           "plain words (write the word itself, e.g. 'red', not '$Color')");
}

Sharing parse_sharing(const std::string& text) {
  if (text == "shared") return Sharing::shared;
  if (text == "private") return Sharing::private_;
  if (text == "core") return Sharing::core;
  throw sdk::Error(sdk::codes::kBadConfig,
                   "lexicon.sharing must be shared, private or core, not '" + text + "'");
}

const char* to_string(Sharing s) {
  switch (s) {
    case Sharing::shared:
      return "shared";
    case Sharing::private_:
      return "private";
    case Sharing::core:
      return "core";
  }
  return "shared";
}

Naturalizer::Naturalizer(std::shared_ptr<kernel::Runtime> runtime, NaturalizeOptions options)
    : runtime_(std::move(runtime)), options_(std::move(options)) {
  if (!runtime_ || !runtime_->parser || !runtime_->scorer)
    throw sdk::Error(sdk::codes::kInternal,
                     "naturalization needs a runtime with parser and scorer");
  if (!options_.warn) options_.warn = warn_stderr;
  // The page check runs in restore_from_rows(), when no rule snapshot vouches for the file.
  LexiconStoreOptions store_options = options_.store;
  store_options.check_on_open = false;
  store_ = std::make_unique<LexiconStore>(options_.store_path, store_options);
  restore();
  if (const char* refusal = store_->write_refusal())
    options_.warn("lexicon store '" + store_->path() + "' is " +
                  (std::string(refusal) == lexicon_codes::kFull ? "full" : "read-only") +
                  ": it serves its " + std::to_string(rules_.size()) +
                  (rules_.size() == 1 ? " rule" : " rules") +
                  "; definitions and deletions are refused with " + refusal +
                  ", and what accepts teach lasts only until this process ends");
  if (!options_.preload.empty()) preload(options_.preload);
}

Naturalizer::~Naturalizer() = default;

void Naturalizer::restore() {
  store_->changed_elsewhere();             // the baseline for refresh(), taken before reading
  learned_mark_ = store_->learned_mark();  // likewise: what is learned later is read again
  if (!restore_from_snapshot()) restore_from_rows();
  record_quarantines();
  // Counters last: they change on every accept without moving the mark, so no snapshot has them.
  for (const auto& u : store_->nonzero_uses())
    if (by_id_.count(u.rule)) runtime_->usage->set(u.rule, {u.by_author, u.by_others});
  initial_weights_ = save_weights();
  fold_legacy_user_weights();
  load_weights(kWeightsKey);
}

// Stores of older builds kept lexicon.weights = per_user's weights under one key per user
// ("user:X", with the scorer's own partition "" or X); the scorer now partitions by user
// itself, so they are folded into the one key, partition X (docs/naturalization.md §5 "Learned
// state"). Once, in one transaction; a read-only store keeps them (and says so). A saved whole
// state is read by the scorer, whose format it is (sdk::StateWeights), its answer checked before
// it is stored (docs/plugins-untrusted.md): a scorer that cannot read it keeps it unserved.
void Naturalizer::fold_legacy_user_weights() {
  const auto legacy = store_->legacy_user_weight_keys();
  if (legacy == 0) return;
  if (store_->write_refusal()) {
    options_.warn("lexicon store '" + store_->path() + "' holds " + std::to_string(legacy) +
                  " per-user weight key(s) of an older Flipper (user:NAME); a store that is "
                  "read-only cannot fold them into the scorer's per-user partitions, so they "
                  "are not served until it is opened writable");
    return;
  }
  const auto& scorer = runtime_->scorer;
  const auto* reader = dynamic_cast<const sdk::StateWeights*>(scorer.borrow());
  std::map<std::string, std::string> why;  // a kept key: why its state was not read
  const auto state_weights =
      [&](const std::string& key,
          const std::string& state) -> std::optional<std::vector<StoredWeightChange>> {
    if (reader == nullptr) {
      why[key] = scorer.id().label() + " does not read its saved states as weights";
      return std::nullopt;
    }
    std::optional<std::vector<sdk::WeightChange>> read;
    try {
      read = kernel::checked_state_weights(scorer, *reader, state);
    } catch (const sdk::Error& e) {  // plugin_error, invalid_weights, or the plugin's own code
      why[key] = std::string("[") + e.code() + "] " + e.what();
      return std::nullopt;
    }
    if (!read) {
      why[key] = scorer.id().label() + " does not read it as a state it saved";
      return std::nullopt;
    }
    std::vector<StoredWeightChange> out;
    out.reserve(read->size());
    for (auto& w : *read)
      out.push_back({std::move(w.model), std::move(w.feature), w.weight, w.aux});
    return out;
  };
  const auto kept = store_->fold_user_weights(kWeightsKey, state_weights);
  for (const auto& key : kept) {
    const auto reason = why.find(key);
    options_.warn("lexicon store '" + store_->path() + "': the saved scorer state under '" + key +
                  "' (an older Flipper's per-user state) is not a weight table this build can "
                  "fold into the scorer's per-user partitions; it is kept, not served" +
                  (reason == why.end() ? std::string() : " (" + reason->second + ")"));
  }
}

bool Naturalizer::restore_from_snapshot() {
  if (options_.snapshot_min_rules <= 0) return false;
  SnapshotMiss miss = SnapshotMiss::none;
  auto snapshot = store_->load_snapshot(&miss);
  if (!snapshot) {
    if (miss == SnapshotMiss::damaged)
      options_.warn("lexicon store '" + store_->path() +
                    "': the rule snapshot does not match its checksum; rebuilt from the rules");
    return false;
  }
  if (snapshot->changed > std::max(options_.snapshot_min_rules, snapshot->rules / 8))
    return false;  // cheaper to read the rows once and leave a fresh snapshot
  by_id_.reserve(static_cast<std::size_t>(snapshot->rules + snapshot->changed));
  shapes_.reserve(static_cast<std::size_t>(snapshot->rules + snapshot->changed));
  rules_.reserve(static_cast<std::size_t>(snapshot->rules + snapshot->changed));
  // The blob is checked whole before the first rule is handed out: false means nothing was added.
  if (!read_rule_snapshot(snapshot->data, [&](const StoredRuleView& r) { add_viewed(r); })) {
    options_.warn("lexicon store '" + store_->path() +
                  "': the rule snapshot does not decode; rebuilt from the rules");
    return false;
  }
  mark_ = snapshot->mark;
  startup_.from_snapshot = true;
  startup_.snapshot_rules = snapshot->rules;
  snapshot.reset();  // the blob's memory, before the rows changed since are read
  apply(store_->changes_since(mark_));
  return true;
}

void Naturalizer::restore_from_rows() {
  // No snapshot vouches for the file: check every page, as a plain open does.
  store_->verify();
  RuleSnapshotWriter writer;
  const bool keep =
      options_.snapshot_min_rules > 0 && !store_->read_only() && store_->path() != ":memory:";
  const LiveRulesRead read = store_->read_live_rules([&](StoredRule&& r) {
    if (keep) writer.add(r);
    add_stored(std::move(r));
  });
  mark_ = read.mark;
  if (keep && static_cast<std::int64_t>(writer.size()) >= options_.snapshot_min_rules) {
    const auto n = static_cast<std::int64_t>(writer.size());
    startup_.snapshot_saved = store_->save_snapshot(read, n, writer.finish());
  }
}

namespace {
sdk::IncrementalScorer* incremental(sdk::Scorer& scorer) {
  return dynamic_cast<sdk::IncrementalScorer*>(&scorer);
}
}  // namespace

// A whole saved state (older builds, non-incremental scorers) or the initial one, then the
// additive weights: the scorer then holds exactly what any kernel reading the store would hold
// (docs/naturalization.md §5 "Learned state").
void Naturalizer::load_weights(const std::string& key) {
  auto& scorer = *runtime_->scorer.borrow();
  auto state = store_->load_weights(key);
  held_from_state_ = state.has_value();
  runtime_->scorer.call("load_state",
                        [&](sdk::Scorer& s) { s.load_state(state ? *state : initial_weights_); });
  if (auto* inc = incremental(scorer)) {
    std::vector<sdk::WeightChange> changes;
    for (auto& c : store_->weight_changes(key))
      changes.push_back({std::move(c.model), std::move(c.feature), c.weight, c.aux});
    inc->apply_changes(changes);
    inc->commit_changes();
  }
}

void Naturalizer::close_store() {
  store_.reset();
}

void Naturalizer::refresh() {
  // data_version is read before the changes, so a commit racing with this read shows next time.
  if (!store_->changed_elsewhere()) return;
  apply(store_->changes_since(mark_));
  apply(store_->learned_since(learned_mark_));
}

void Naturalizer::apply(const LearnedChanges& learned) {
  for (const auto& u : learned.uses)
    if (by_id_.count(u.rule)) runtime_->usage->set(u.rule, {u.by_author, u.by_others});
  if (std::find(learned.weight_keys.begin(), learned.weight_keys.end(), kWeightsKey) !=
      learned.weight_keys.end())
    load_weights(kWeightsKey);
  learned_mark_ = learned.mark;
}

bool Naturalizer::add_stored(StoredRule&& stored, const std::vector<sdk::RulePtr>& own) {
  if (by_id_.count(stored.id)) return false;
  auto mine = std::find_if(own.begin(), own.end(),
                           [&](const sdk::RulePtr& r) { return r->id == stored.id; });
  sdk::RulePtr rule;
  if (mine != own.end()) {
    rule = *mine;
  } else {
    try {
      rule = rule_from_stored(std::move(stored));  // untouched when it throws
    } catch (const std::exception& e) {
      quarantine(std::move(stored), e.what());
      return false;
    }
  }
  runtime_->parser.call("add_rule", [&](sdk::Parser& p) { p.add_rule(rule); });
  add_live(std::move(rule));
  return true;
}

void Naturalizer::quarantine(StoredRule&& stored, const std::string& reason) {
  // One bad rule must not lock everyone out of a shared lexicon: skip it, say which.
  options_.warn("lexicon store '" + store_->path() + "': rule " + stored.id + " (author '" +
                stored.author + "', head '" + stored.head +
                "') is quarantined, not served: " + reason);
  quarantined_.push_back({std::move(stored), reason});
}

void Naturalizer::add_viewed(const StoredRuleView& viewed) {
  if (by_id_.count(viewed.id)) return;  // before building it: a duplicate costs no rule
  sdk::RulePtr rule;
  try {
    rule = rule_from_stored(viewed);
  } catch (const std::exception&) {
    add_stored(viewed.materialize());  // quarantines it, with the same warning
    return;
  }
  runtime_->parser.call("add_rule", [&](sdk::Parser& p) { p.add_rule(rule); });
  add_live(std::move(rule));
}

void Naturalizer::apply(const LexiconChanges& changes, const std::vector<sdk::RulePtr>& own) {
  for (const auto& stored : changes.added) {
    const RuleUses uses{stored.id, stored.uses_by_author, stored.uses_by_others};
    if (add_stored(StoredRule(stored), own))
      runtime_->usage->set(uses.rule, {uses.by_author, uses.by_others});
  }
  for (const auto& id : changes.deleted) remove_live(id);
  mark_ = changes.mark;
  record_quarantines();
}

void Naturalizer::record_quarantines() {
  // After the reads that met them (a write cannot start inside their read transaction); the
  // store writes each rule and reason once, whichever process meets it first.
  for (; quarantines_recorded_ < quarantined_.size(); ++quarantines_recorded_) {
    const auto& q = quarantined_[quarantines_recorded_];
    store_->record_quarantine(q.stored, q.reason);
  }
}

std::string Naturalizer::save_weights() const {
  return runtime_->scorer.call("save_state", [](const sdk::Scorer& s) { return s.save_state(); });
}

void Naturalizer::add_live(sdk::RulePtr rule) {
  by_id_.emplace(std::string_view(rule->id), rule);  // the key views the id the value keeps
  shapes_.push_back(shape_hash(*rule));
  rules_.push_back(std::move(rule));
}

void Naturalizer::remove_live(const std::string& id) {
  auto rule = find_rule(id);
  if (!rule) return;
  runtime_->parser.call("remove_rule", [&](sdk::Parser& p) { p.remove_rule(id); });
  runtime_->usage->erase(id);
  by_id_.erase(id);
  const auto at = std::find(rules_.begin(), rules_.end(), rule) - rules_.begin();
  rules_.erase(rules_.begin() + at);
  shapes_.erase(shapes_.begin() + at);
}

bool Naturalizer::visible(const sdk::Rule& rule, const std::string& user) const {
  return !rule.induced || visible_author(options_.sharing, rule.author, user);
}

std::function<bool(const sdk::Rule&)> Naturalizer::visibility_for(const std::string& user) const {
  if (options_.sharing == Sharing::shared) return {};  // every rule: no filter cost
  return [this, user](const sdk::Rule& r) { return visible(r, user); };
}

bool Naturalizer::exists_for(const sdk::Rule& rule, const std::string& author) const {
  // A scan of 8 bytes per rule (0.1 ms at 100k rules), run a few times per define: cheaper
  // overall than a hash map built for every rule at start-up.
  const std::uint64_t shape = shape_hash(rule);
  for (std::size_t i = 0; i < shapes_.size(); ++i)
    if (shapes_[i] == shape && visible(*rules_[i], author) && same_rule(*rules_[i], rule))
      return true;
  return false;
}

sdk::RulePtr Naturalizer::find_rule(const std::string& id) const {
  auto it = by_id_.find(id);
  return it == by_id_.end() ? nullptr : it->second;
}

namespace {
std::string conflicts_message(const std::vector<DefineConflict>& conflicts) {
  constexpr std::size_t kShown = 5;
  std::string m = "the definition would change how " + std::to_string(conflicts.size()) +
                  " phrase(s) of other users read (lexicon.conflicts = refuse); nothing was "
                  "stored:";
  for (std::size_t i = 0; i < conflicts.size() && i < kShown; ++i) {
    const auto& c = conflicts[i];
    m += " '" + c.phrase + "' (" + c.user + "): ";
    m += c.kind == "first_reading"
             ? "first reading " + (c.before.empty() ? "(none)" : c.before) + " becomes " + c.after
             : "gains a reading (" + std::to_string(c.readings_before) + " -> " +
                   std::to_string(c.readings_after) + ")";
    m += ";";
  }
  if (conflicts.size() > kShown)
    m += " and " + std::to_string(conflicts.size() - kShown) + " more;";
  m.pop_back();
  return m;
}
}  // namespace

std::string preview_id(std::size_t index) {
  return "new" + std::to_string(index + 1);
}

namespace {
// Leaves out the rules a preview's author dropped (docs/naturalization.md §5 "Preview").
void drop_rules(const std::vector<std::string>& drop,
                std::vector<std::shared_ptr<sdk::Rule>>& fresh, std::vector<std::string>& dropped) {
  if (drop.empty()) return;
  std::vector<bool> gone(fresh.size(), false);
  for (const auto& id : drop) {
    std::size_t k = 0;
    while (k < fresh.size() && preview_id(k) != id) ++k;
    if (k == fresh.size())
      throw sdk::Error(sdk::codes::kBadRequest,
                       "drop: '" + id.substr(0, 40) + "' names none of the " +
                           std::to_string(fresh.size()) + " rules this definition induces (new1.." +
                           preview_id(fresh.size() - (fresh.empty() ? 0 : 1)) + ")");
    gone[k] = true;
  }
  if (std::all_of(gone.begin(), gone.end(), [](bool g) { return g; }))
    throw sdk::Error(sdk::codes::kBadRequest,
                     "drop leaves none of the definition's rules; cancel the definition instead");
  std::vector<std::shared_ptr<sdk::Rule>> kept;
  for (std::size_t k = 0; k < fresh.size(); ++k) {
    if (gone[k])
      dropped.push_back(preview_id(k));
    else
      kept.push_back(std::move(fresh[k]));
  }
  fresh = std::move(kept);
}
}  // namespace

DefineOutcome Naturalizer::define(const DefineRequest& req) {
  check_head_tokens(req.head);
  refresh();  // induce against every rule committed so far, by any process
  Inducer inducer(runtime_->parser, runtime_->scorer, options_.induction, runtime_->usage.get());
  // induction.view=everyone: the head and body parses see every user's rules, as the 2018
  // server's one grammar did in its private runs (docs/naturalization.md §4.1).
  const auto visible_rules = options_.induction_sees_everyone
                                 ? std::function<bool(const sdk::Rule&)>()
                                 : visibility_for(req.user);
  PreparedDefinition prepared = inducer.prepare(
      {req.head, req.body, req.user, req.body_ranks, req.body_programs}, visible_rules, req.stop);

  DefineOutcome out;
  out.body = prepared.body;
  sdk::Program winner = prepared.body;
  bool rewritten = false;
  if (options_.generalize && runtime_->rewriter && req.before && req.exec) {
    GeneralizeOptions gopts;
    gopts.perturbed_checks = options_.perturbed_checks;
    Generalizer generalizer(runtime_->rewriter, runtime_->similarity, *req.exec, gopts);
    const int n = static_cast<int>(prepared.head_tokens.size());
    GeneralizeResult g = generalizer.generalize(
        prepared.head_tokens, prepared.body, *req.before,
        [&](const sdk::Program& p) { return best_packing_score(prepared.head_chart, p, n); });
    out.generalization_ran = true;
    if (!g.body_won && g.winner) {
      winner = g.winner;
      rewritten = true;
      out.generalized = g.winner;
      out.generalized_rewriting = g.winner_rewriting;
    }
    for (const auto& c : g.candidates)
      if (!c.rejected_reason.empty())
        out.discarded.push_back({c.program, c.rewriting, c.rejected_reason});
    out.perturbations = g.perturbations;
    if (g.winner_index < g.candidates.size()) {
      out.perturbed_passed = g.candidates[g.winner_index].perturbed_passed;
      out.perturbed_failed = g.candidates[g.winner_index].failed_checks;
    }
  }

  InductionResult induced = inducer.induce(
      prepared, winner, rewritten, [&](const sdk::Rule& r) { return exists_for(r, req.user); });

  if (const sdk::StopCause cause = req.stop.cause(); cause != sdk::StopCause::none)
    throw sdk::StoppedError(cause, std::string("deadline exceeded before the definition was stored "
                                               "(stopped: ") +
                                       sdk::to_string(cause) +
                                       ": session.cpu_budget_ms or session.deadline_ms); nothing "
                                       "was stored");

  std::vector<std::shared_ptr<sdk::Rule>> fresh;
  for (auto& r : induced.rules) {
    auto rule = std::make_shared<sdk::Rule>(std::move(r));
    rule->author = req.user;
    rule->head = req.head;
    rule->body = req.body;
    fresh.push_back(std::move(rule));
  }
  drop_rules(req.drop, fresh, out.dropped);
  // Conflicts before they happen (docs/naturalization.md §5 "Conflicts"): shown, or refused. A
  // preloaded definition is the site's own lexicon, shown to no one, and a replicated one was
  // checked where it was made: neither is checked here.
  if (req.via != "preload" && req.via != "replicate")
    out.conflicts = find_conflicts(req.user, fresh, req.stop);
  if (!out.conflicts.empty() && options_.conflicts == ConflictPolicy::refuse && !req.dry_run)
    throw sdk::Error(naturalize_codes::kDefinitionConflicts, conflicts_message(out.conflicts));
  if (req.dry_run) {
    out.rules.assign(fresh.begin(), fresh.end());
    return out;
  }

  // Commit definition + rules in one transaction, where the store assigns their ids, before
  // anything becomes visible: a failed commit leaves parser and store unchanged.
  const std::int64_t now = static_cast<std::int64_t>(std::time(nullptr));
  std::vector<StoredRule> stored;
  stored.reserve(fresh.size());
  for (const auto& rule : fresh) stored.push_back(stored_from_rule(*rule, 0));
  // lexicon.moderation = hold_new: a user's definition waits for a researcher, serving no one
  // (its author included), and so does one another site made (replicated: this site's researcher
  // decides what serves here, docs/ros2.md "Moderation across sites"); preloaded and imported
  // ones are the site's own (docs/naturalization.md §5 "Moderation").
  if (options_.moderation == Moderation::hold_new && (req.via.empty() || req.via == "replicate")) {
    out.held = store_->hold_definition(
        {0, req.head, req.body, req.user, now, {}, req.study, req.via}, stored);
    out.rules.assign(fresh.begin(), fresh.end());
    return out;
  }
  DefinitionCommit commit = store_->commit_definition(
      {0, req.head, req.body, req.user, now, {}, req.study, req.via}, std::move(stored));
  out.definition = commit.definition;
  std::vector<sdk::RulePtr> rules;
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    fresh[i]->id = commit.rules[i].id;
    fresh[i]->created = commit.rules[i].created;
    rules.push_back(fresh[i]);
  }
  // Everything up to this commit, others' rules first (creation order), then ours.
  apply(store_->changes_since(mark_), rules);
  out.rules = std::move(rules);
  out.stored = true;
  return out;
}

std::vector<HeldDefinition> Naturalizer::pending() const {
  return store_->held();
}

std::vector<sdk::RulePtr> Naturalizer::approve(const std::string& moderator,
                                               const std::string& id) {
  refresh();
  const DefinitionCommit commit =
      store_->approve_held(id, {moderator, {}, {}}, static_cast<std::int64_t>(std::time(nullptr)));
  apply(store_->changes_since(mark_));
  std::vector<sdk::RulePtr> rules;
  for (const auto& r : commit.rules)
    if (auto rule = find_rule(r.id)) rules.push_back(std::move(rule));
  return rules;
}

void Naturalizer::reject(const std::string& moderator, const std::string& id,
                         const std::string& reason) {
  (void)store_->reject_held(id, {moderator, {}, reason},
                            static_cast<std::int64_t>(std::time(nullptr)));
}

std::vector<RuleListing> Naturalizer::rules(const std::string& user,
                                            const std::optional<std::string>& author) const {
  std::vector<RuleListing> out;
  for (const auto& r : rules_) {
    if (!visible(*r, user) || (author && r->author != *author)) continue;
    const sdk::RuleUses uses = runtime_->usage->uses(r->id);
    out.push_back({r, uses.by_author, uses.by_others});
  }
  return out;
}

void Naturalizer::delete_rule(const std::string& user, const std::string& id) {
  const DeleteResult r = store_->delete_rule(
      id, user, static_cast<std::int64_t>(std::time(nullptr)),
      [&](const std::string& author) { return visible_author(options_.sharing, author, user); });
  if (r.status == DeleteStatus::not_found)
    throw sdk::Error(naturalize_codes::kNotFound, "no rule with id '" + id + "'");
  if (r.status == DeleteStatus::forbidden)
    throw sdk::Error(naturalize_codes::kForbidden, "rule " + id + " belongs to '" + r.author +
                                                       "'; only its author may delete it");
  apply(store_->changes_since(mark_));  // removes it here (and picks up others' changes)
}

void Naturalizer::on_accept(const std::string& user, const std::vector<sdk::RulePtr>& used) {
  // A store that opened degraded cannot keep what the accept taught: the session keeps it in
  // memory (counters counted, weights learnt), as the start-up warning said.
  if (store_->write_refusal()) return;
  std::vector<RuleUses> deltas;
  std::vector<sdk::RulePtr> rules;
  for (const auto& r : used) {
    if (!r || !r->induced || !by_id_.count(r->id)) continue;
    if (std::any_of(deltas.begin(), deltas.end(),
                    [&](const RuleUses& u) { return u.rule == r->id; }))
      continue;
    const bool own = r->author == user;
    deltas.push_back({r->id, own ? 1u : 0u, own ? 0u : 1u});
    rules.push_back(r);
  }
  // An incremental scorer's changed weights are added to the stored sums; any other scorer's
  // whole state replaces the stored one (last writer wins). Either way in the accept's
  // transaction, with the counters.
  std::vector<RuleUses> totals;
  LexiconStore::WeightSums sums;
  auto* inc = incremental(*runtime_->scorer.borrow());
  if (inc) {
    std::vector<StoredWeightChange> changes;
    for (auto& c : inc->pending_changes())
      changes.push_back({std::move(c.model), std::move(c.feature), c.weight, c.aux});
    totals = store_->record_accept(deltas, kWeightsKey, changes, &sums);
  } else {
    totals = store_->record_accept(deltas, kWeightsKey, save_weights());
  }
  // The stored totals include other processes' uses.
  for (std::size_t i = 0; i < rules.size(); ++i)
    runtime_->usage->set(rules[i]->id, {totals[i].by_author, totals[i].by_others});
  hold_stored_weights(inc, sums);
}

// The scorer learned in memory; the stored sums are the truth every other kernel reads, and
// floating-point sums taken in another order may differ in the last bit: hold the stored ones
// (docs/naturalization.md §5 "Learned state").
void Naturalizer::hold_stored_weights(sdk::IncrementalScorer* inc,
                                      const LexiconStore::WeightSums& sums) {
  if (store_->changed_elsewhere() || !inc || held_from_state_) {
    // Someone else committed since this kernel last looked (its weights may lag the stored sums
    // by more than this accept), or the base is a saved state: catch up whole.
    apply(store_->changes_since(mark_));
    apply(store_->learned_since(learned_mark_));
    load_weights(kWeightsKey);
    return;
  }
  // The changed weights held exactly the sums before (0 + sum, as any kernel loads them): undo
  // the learning, take each back to 0 (x + -x is exactly 0) and add the new sum, so they are
  // exactly 0 + sum after, in O(changed weights).
  std::vector<sdk::WeightChange> zero, after;
  for (const auto& c : sums.before) zero.push_back({c.model, c.feature, -c.weight, -c.aux});
  for (const auto& c : sums.after) after.push_back({c.model, c.feature, c.weight, c.aux});
  runtime_->scorer.call("apply_changes", [&](sdk::Scorer&) {
    inc->discard_changes();
    inc->apply_changes(zero);
    inc->apply_changes(after);
  });
}

}  // namespace flipper::naturalization
