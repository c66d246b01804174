// flipper lexicon log|diff|tag|revert: the lexicon's history and its governance
// (docs/naturalization.md §5 "History and governance").
//   log [--rule ID] [--author A] [--json]   every change, in commit order, with the tags
//   diff A B [--json]                        rules of point A against point B
//   tag NAME [--user U]                      names the current point of the history
//   revert TO [--user U]                     live rules := those at TO (new entries; nothing
//   erased)
// A point is a tag, `#N` (history entry N), `@SECONDS` or `YYYY-MM-DDTHH:MM:SSZ` (the last entry
// made then), `now`, or (diff only) the path of another store (its live rules).
#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"
#include "lexicon_common.hpp"

namespace flipper::cli {
namespace {
namespace nat = naturalization;
using nlohmann::json;

struct HistoryArgs {
  CommonOptions common;
  std::string rule, author, user;
  std::string a, b;  // diff's points, tag's name, revert's target
  bool json = false;
};

std::string utc(std::int64_t seconds) {
  const auto t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

/// `@SECONDS` or `YYYY-MM-DDTHH:MM:SS[Z]` (UTC); nullopt when `text` is neither.
std::optional<std::int64_t> parse_time(const std::string& text) {
  if (text.size() > 1 && text[0] == '@') {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(text.c_str() + 1, &end, 10);
    if (errno == 0 && end != nullptr && *end == '\0' && v >= 0) return v;
    return std::nullopt;
  }
  std::tm tm{};
  const char* end = strptime(text.c_str(), "%Y-%m-%dT%H:%M:%S", &tm);
  if (end == nullptr || (*end != '\0' && std::string(end) != "Z")) return std::nullopt;
  return static_cast<std::int64_t>(timegm(&tm));
}

/// A point of a store's history: its label and the rules live there.
struct Point {
  std::string label;
  std::int64_t seq = -1;  // -1: another store's live rules
  std::vector<nat::StoredRule> rules;
};

/// The entry `text` names in `store`: a tag, #N, a time or `now`; nullopt when none of them.
std::optional<std::pair<std::int64_t, std::string>> resolve_seq(const nat::LexiconStore& store,
                                                                const std::string& text) {
  if (auto tag = store.find_tag(text))
    return std::make_pair(tag->seq,
                          "tag " + tag->name + " (entry " + std::to_string(tag->seq) + ")");
  if (text == "now") {
    const std::int64_t head = store.history_head();
    return std::make_pair(head, "now (entry " + std::to_string(head) + ")");
  }
  if (text.size() > 1 && text[0] == '#') {
    char* end = nullptr;
    const long long v = std::strtoll(text.c_str() + 1, &end, 10);
    if (end != nullptr && *end == '\0' && v >= 0) {
      if (v > store.history_head())
        throw sdk::Error(sdk::codes::kBadRequest, "no history entry " + text + " (the last is #" +
                                                      std::to_string(store.history_head()) + ")");
      return std::make_pair(static_cast<std::int64_t>(v), "entry " + std::to_string(v));
    }
  }
  if (auto t = parse_time(text)) {
    const std::int64_t seq = store.history_at_time(*t);
    return std::make_pair(seq, utc(*t) + " (entry " + std::to_string(seq) + ")");
  }
  return std::nullopt;
}

Point resolve_point(const nat::LexiconStore& store, const std::string& text, bool allow_store) {
  if (auto seq = resolve_seq(store, text))
    return {seq->second, seq->first, store.rules_at(seq->first)};
  std::error_code ec;
  if (allow_store && std::filesystem::is_regular_file(text, ec)) {
    const nat::LexiconStore other(text);
    return {"store " + text, -1, other.rules()};
  }
  throw sdk::Error(sdk::codes::kBadRequest,
                   "'" + text + "' is no tag of '" + store.path() +
                       "', entry (#N), time (@SECONDS, YYYY-MM-DDTHH:MM:SSZ) or 'now'" +
                       (allow_store ? ", nor a lexicon store file" : ""));
}

std::string history_rule_text(const nat::StoredRule& r) {
  std::string rhs;
  for (const auto& s : r.rhs) rhs += (rhs.empty() ? "" : " ") + s;
  return r.lhs + " -> " + rhs + " => " + r.semantics;
}

/// What decides parses (lexicon_checksum's content): two rules with the same key are the same
/// rule for a diff, whatever their ids.
std::string rule_key(const nat::StoredRule& r) {
  return r.author + '\x1f' + history_rule_text(r);
}

json entry_json(const nat::HistoryEntry& e) {
  json j{{"seq", e.seq},       {"time", e.time}, {"author", e.author}, {"action", e.action},
         {"effect", e.effect}, {"head", e.head}, {"body", e.body}};
  if (!e.rule.empty()) j["rule"] = e.rule;
  if (!e.source_rule.empty()) j["source_rule"] = e.source_rule;
  if (e.definition != 0) j["definition"] = e.definition;
  if (!e.study.empty()) j["study"] = e.study;
  if (!e.site.empty()) j["site"] = e.site;
  if (!e.note.empty()) j["note"] = e.note;
  return j;
}

int show_log(const HistoryArgs& a) {
  const auto store = open_lexicon_store(a.common);
  nat::HistoryFilter filter;
  if (!a.rule.empty()) filter.rule = a.rule;
  if (!a.author.empty()) filter.author = a.author;
  const auto entries = store->history(filter);
  const auto tags = store->tags();
  if (a.json) {
    json list = json::array(), tag_list = json::array();
    for (const auto& e : entries) list.push_back(entry_json(e));
    for (const auto& t : tags)
      tag_list.push_back({{"name", t.name},
                          {"seq", t.seq},
                          {"time", t.time},
                          {"author", t.author},
                          {"checksum", t.checksum}});
    std::cout << json{{"store", store->path()}, {"entries", list}, {"tags", tag_list}}.dump(2)
              << "\n";
    return kExitOk;
  }
  std::multimap<std::int64_t, const nat::LexiconTag*> by_seq;
  for (const auto& t : tags) by_seq.emplace(t.seq, &t);
  const bool filtered = filter.rule || filter.author;
  for (const auto& e : entries) {
    std::string body;
    for (const auto& line : e.body) body += (body.empty() ? "" : "; ") + line;
    std::cout << "#" << e.seq << " " << utc(e.time) << " " << e.author << " " << e.action;
    if (!e.rule.empty()) std::cout << " " << (e.effect == "remove" ? "-" : "+") << e.rule;
    if (!e.source_rule.empty()) std::cout << " (copy of " << e.source_rule << ")";
    if (e.definition != 0) std::cout << " def " << e.definition;
    if (!e.head.empty()) std::cout << " '" << e.head << "' := '" << body << "'";
    if (!e.study.empty()) std::cout << " study=" << e.study;
    if (!e.site.empty()) std::cout << " site=" << e.site;
    if (!e.note.empty()) std::cout << " [" << e.note << "]";
    std::cout << "\n";
    if (!filtered)
      for (auto [it, end] = by_seq.equal_range(e.seq); it != end; ++it)
        std::cout << "   tag " << it->second->name << " by " << it->second->author << " at "
                  << utc(it->second->time) << " (checksum " << it->second->checksum << ")\n";
  }
  std::cout << entries.size() << (entries.size() == 1 ? " entry" : " entries") << " in "
            << store->path() << "\n";
  return kExitOk;
}

int show_diff(const HistoryArgs& a) {
  const auto store = open_lexicon_store(a.common);
  const Point from = resolve_point(*store, a.a, true);
  const Point to = resolve_point(*store, a.b, true);
  // Multisets of rule content: a re-created rule (new id) is the same rule.
  std::multimap<std::string, const nat::StoredRule*> left, right;
  for (const auto& r : from.rules) left.emplace(rule_key(r), &r);
  for (const auto& r : to.rules) right.emplace(rule_key(r), &r);
  std::vector<const nat::StoredRule*> removed, added;
  for (auto it = left.begin(); it != left.end();) {
    const auto key = it->first;
    const auto n_left = left.count(key), n_right = right.count(key);
    for (std::size_t i = n_right; i < n_left; ++i, ++it) removed.push_back(it->second);
    it = left.upper_bound(key);
  }
  for (auto it = right.begin(); it != right.end();) {
    const auto key = it->first;
    const auto n_left = left.count(key), n_right = right.count(key);
    for (std::size_t i = n_left; i < n_right; ++i, ++it) added.push_back(it->second);
    it = right.upper_bound(key);
  }
  const auto by_created = [](const nat::StoredRule* x, const nat::StoredRule* y) {
    return x->created < y->created;
  };
  std::sort(removed.begin(), removed.end(), by_created);
  std::sort(added.begin(), added.end(), by_created);
  const std::string sum_from = nat::lexicon_checksum(from.rules);
  const std::string sum_to = nat::lexicon_checksum(to.rules);
  if (a.json) {
    const auto list = [](const std::vector<const nat::StoredRule*>& v) {
      json out = json::array();
      for (const auto* r : v)
        out.push_back({{"id", r->id}, {"author", r->author}, {"rule", history_rule_text(*r)}});
      return out;
    };
    std::cout
        << json{{"from",
                 {{"point", from.label}, {"rules", from.rules.size()}, {"checksum", sum_from}}},
                {"to", {{"point", to.label}, {"rules", to.rules.size()}, {"checksum", sum_to}}},
                {"removed", list(removed)},
                {"added", list(added)},
                {"same_order", sum_from == sum_to}}
               .dump(2)
        << "\n";
    return kExitOk;
  }
  std::cout << "--- " << from.label << ": " << from.rules.size() << " rules, checksum " << sum_from
            << "\n+++ " << to.label << ": " << to.rules.size() << " rules, checksum " << sum_to
            << "\n";
  for (const auto* r : removed)
    std::cout << "- " << r->id << " " << r->author << " " << history_rule_text(*r) << "\n";
  for (const auto* r : added)
    std::cout << "+ " << r->id << " " << r->author << " " << history_rule_text(*r) << "\n";
  std::cout << removed.size() << " removed, " << added.size() << " added";
  if (removed.empty() && added.empty() && sum_from != sum_to)
    std::cout << " (the same rules in another creation order)";
  std::cout << "\n";
  return kExitOk;
}

int make_tag(const HistoryArgs& a) {
  const auto store = open_lexicon_store(a.common);
  const auto t =
      store->tag(a.a, lexicon_user(a.user), static_cast<std::int64_t>(std::time(nullptr)));
  std::cout << "tag " << t.name << " = entry " << t.seq << " of " << store->path() << " ("
            << store->rules_at(t.seq).size() << " live rules, checksum " << t.checksum << ")\n";
  return kExitOk;
}

int revert(const HistoryArgs& a) {
  const auto store = open_lexicon_store(a.common);
  const auto target = resolve_seq(*store, a.a);
  if (!target)
    throw sdk::Error(sdk::codes::kBadRequest,
                     "'" + a.a + "' is no tag of '" + store->path() +
                         "', entry (#N), time (@SECONDS, YYYY-MM-DDTHH:MM:SSZ) or 'now'");
  const auto out =
      store->revert_to(target->first, {lexicon_user(a.user), {}, "revert to " + target->second},
                       static_cast<std::int64_t>(std::time(nullptr)));
  std::cout << "reverted " << store->path() << " to " << target->second << ": "
            << out.removed.size() << " rules deleted, " << out.restored.size()
            << " re-created; checksum " << nat::lexicon_checksum(store->rules()) << "\n";
  for (const auto& id : out.removed) std::cout << "- " << id << "\n";
  for (const auto& [id, from] : out.restored)
    std::cout << "+ " << id << " (copy of " << from << ")\n";
  return kExitOk;
}

}  // namespace

std::unique_ptr<naturalization::LexiconStore> open_lexicon_store(const CommonOptions& common) {
  const std::string path =
      naturalization::NaturalizeOptions::from_config(load_config(common)).store_path;
  std::error_code ec;
  if (path != ":memory:" && !std::filesystem::exists(path, ec))
    throw sdk::Error(sdk::codes::kBadConfig,
                     "no lexicon store at '" + path + "' (lexicon.path; --set lexicon.path=FILE)");
  naturalization::LexiconStoreOptions options;
  options.site = load_config(common).get(naturalization::keys::kSite);
  return std::make_unique<naturalization::LexiconStore>(path, options);
}

std::string lexicon_user(const std::string& user) {
  if (!user.empty()) return user;
  const char* env = std::getenv("USER");
  return env != nullptr && *env != '\0' ? env : "unknown";
}

void add_lexicon_history_commands(CLI::App& cmd) {
  static HistoryArgs log_args, diff_args, tag_args, revert_args;
  auto* log = cmd.add_subcommand("log", "Every change to the lexicon, in commit order");
  add_common_options(*log, log_args.common);
  log->add_option("--rule", log_args.rule, "Only the entries of this rule (and its copies)");
  log->add_option("--author", log_args.author, "Only the changes this user made");
  log->add_flag("--json", log_args.json, "Print the entries and tags as one JSON object");
  on_run(*log, guarded("log", show_log, log_args));

  auto* diff = cmd.add_subcommand("diff", "Rules of point A against point B");
  add_common_options(*diff, diff_args.common);
  diff->add_option("a", diff_args.a,
                   "A tag, #N, @SECONDS, YYYY-MM-DDTHH:MM:SSZ, now, or a store file")
      ->required();
  diff->add_option("b", diff_args.b, "The same, for the other side")->required();
  diff->add_flag("--json", diff_args.json, "Print the difference as one JSON object");
  on_run(*diff, guarded("diff", show_diff, diff_args));

  auto* tag = cmd.add_subcommand("tag", "Name the current point of the lexicon's history");
  add_common_options(*tag, tag_args.common);
  tag->add_option("name", tag_args.a, "A letter, then letters, digits, '.', '_', '-'")->required();
  tag->add_option("--user", tag_args.user, "Who tags (default: $USER)");
  on_run(*tag, guarded("tag", make_tag, tag_args));

  auto* rev = cmd.add_subcommand(
      "revert", "Make the live rules those of a tag or time (new history entries; nothing erased)");
  add_common_options(*rev, revert_args.common);
  rev->add_option("to", revert_args.a, "A tag, #N, @SECONDS, YYYY-MM-DDTHH:MM:SSZ")->required();
  rev->add_option("--user", revert_args.user, "Who reverts (default: $USER)");
  on_run(*rev, guarded("revert", revert, revert_args));
}

}  // namespace flipper::cli
