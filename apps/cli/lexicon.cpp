// flipper lexicon list|export|import|delete (log|diff|tag|revert: lexicon_history.cpp): the store
// of the config's lexicon.path.
//   list [--author A] [--json]  live rules: id, author, how, uses (by author/by others), the rule
//   delete ID --user U      deletes U's rule ID (forbidden for others' rules; history kept)
//   export FILE|-           JSON Lines copy of the whole store (LexiconStore::export_jsonl)
//   import FILE|-           definitions replayed through induction (docs/naturalization.md §5:
//   rules
//                           are always induced by this system), one durable transaction each,
//                           definitions the store already holds skipped; nothing stored changes
//   import --restore FILE   verbatim copy (rules, counters, deletions, weights) into an EMPTY
//                           store only, for backups; every rule is checked before the commit
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <tuple>

#include "commands.hpp"
#include "common.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/lexicon_store.hpp"
#include "flipper/naturalization/naturalizer.hpp"
#include "flipper/sdk/errors.hpp"
#include "lexicon_common.hpp"

namespace flipper::cli {

namespace {

struct LexiconArgs {
  CommonOptions common;
  std::string file;
  std::string author;
  bool restore = false;
  bool json = false;
  std::string rule_id;  // delete
  std::string user;     // delete: who asks (only a rule's author may delete it)
};

int error(const std::string& what, const std::string& code, const std::string& message,
          int status) {
  return report_error("lexicon " + what, code, message, status);
}

std::string store_path(const kernel::Config& config) {
  return naturalization::NaturalizeOptions::from_config(config).store_path;
}

/// Opens an existing store (reading never creates one).
std::unique_ptr<naturalization::LexiconStore> open_existing(const std::string& path) {
  std::error_code ec;
  if (path != ":memory:" && !std::filesystem::exists(path, ec))
    throw sdk::Error(sdk::codes::kBadConfig,
                     "no lexicon store at '" + path + "' (lexicon.path; --set lexicon.path=FILE)");
  return std::make_unique<naturalization::LexiconStore>(path);
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : " ") + s;
  return out;
}

int list_rules(const LexiconArgs& a) {
  const auto store = open_existing(store_path(load_config(a.common)));
  std::vector<naturalization::StoredRule> rules;
  std::vector<std::pair<naturalization::StoredRule, std::string>> quarantined;
  for (auto& r : store->rules()) {
    if (!a.author.empty() && r.author != a.author) continue;
    if (auto why = naturalization::quarantine_reason(r))
      quarantined.emplace_back(std::move(r), *why);
    else
      rules.push_back(std::move(r));
  }
  std::vector<naturalization::PreloadFailure> preload_failures;
  for (auto& f : store->preload_failures())
    if (a.author.empty() || f.author == a.author) preload_failures.push_back(std::move(f));
  std::size_t w_id = 2, w_author = 6, w_how = 3, w_uses = 4;
  std::vector<std::string> uses;
  for (const auto& r : rules) {
    uses.push_back(std::to_string(r.uses_by_author) + "/" + std::to_string(r.uses_by_others));
    w_id = std::max(w_id, r.id.size());
    w_author = std::max(w_author, r.author.size());
    w_how = std::max(w_how, r.how.size());
    w_uses = std::max(w_uses, uses.back().size());
  }
  if (a.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& r : rules)
      list.push_back({{"id", r.id},
                      {"author", r.author},
                      {"how", r.how},
                      {"lhs", r.lhs},
                      {"rhs", r.rhs},
                      {"semantics", r.semantics},
                      {"uses_by_author", r.uses_by_author},
                      {"uses_by_others", r.uses_by_others}});
    nlohmann::json held = nlohmann::json::array();
    for (const auto& [r, why] : quarantined)
      held.push_back({{"id", r.id}, {"author", r.author}, {"head", r.head}, {"reason", why}});
    nlohmann::json failed = nlohmann::json::array();
    for (const auto& f : preload_failures)
      failed.push_back({{"file", f.file},
                        {"line", f.line},
                        {"head", f.head},
                        {"author", f.author},
                        {"code", f.code},
                        {"message", f.message}});
    std::cout << nlohmann::json{{"store", store->path()},
                                {"rules", std::move(list)},
                                {"quarantined", std::move(held)},
                                {"preload_failures", std::move(failed)}}
                     .dump(2)
              << "\n";
    return kExitOk;
  }
  const auto row = [&](const std::string& id, const std::string& author, const std::string& how,
                       const std::string& use, const std::string& rule) {
    std::cout << std::left << std::setw(static_cast<int>(w_id + 2)) << id
              << std::setw(static_cast<int>(w_author + 2)) << author
              << std::setw(static_cast<int>(w_how + 2)) << how
              << std::setw(static_cast<int>(w_uses + 2)) << use << rule << "\n";
  };
  row("ID", "AUTHOR", "HOW", "USES", "RULE (uses: by author/by others)");
  for (std::size_t i = 0; i < rules.size(); ++i) {
    const auto& r = rules[i];
    row(r.id, r.author, r.how, uses[i], r.lhs + " -> " + join(r.rhs) + " => " + r.semantics);
  }
  std::cout << rules.size() << (rules.size() == 1 ? " rule" : " rules") << " in " << store->path()
            << "\n";
  // Kept in the file but not served: they no longer load (docs/naturalization.md §5).
  for (const auto& [r, why] : quarantined)
    std::cout << "QUARANTINED " << r.id << " (author '" << r.author << "', head '" << r.head
              << "'): " << r.lhs << " -> " << join(r.rhs) << " => " << r.semantics << ": " << why
              << "\n";
  if (!quarantined.empty()) std::cout << quarantined.size() << " quarantined (not served)\n";
  // Definitions of lexicon.preload that did not load at the last start that read that file.
  for (const auto& f : preload_failures)
    std::cout << "PRELOAD FAILED " << f.file << " line " << f.line << " '" << f.head
              << "' (author '" << f.author << "'): " << f.code << ": " << f.message << "\n";
  if (!preload_failures.empty())
    std::cout << preload_failures.size() << " preloaded definition(s) not loaded\n";
  return kExitOk;
}

int export_store(const LexiconArgs& a) {
  const auto store = open_existing(store_path(load_config(a.common)));
  // A full device must be an error, not a silently short export (code write_failed).
  if (a.file == "-") {
    store->export_jsonl(std::cout, naturalization::quarantine_reason);
    std::cout.flush();
    if (!std::cout || std::fflush(stdout) != 0)
      return error("export", sdk::codes::kWriteFailed,
                   std::string("cannot write standard output: ") + std::strerror(errno),
                   kExitFailed);
    return kExitOk;
  }
  std::ofstream out(a.file);
  if (!out)
    return error("export", sdk::codes::kWriteFailed,
                 "cannot write '" + a.file + "': " + std::strerror(errno), kExitFailed);
  store->export_jsonl(out, naturalization::quarantine_reason);
  out.flush();
  if (out) out.close();
  if (!out)
    return error("export", sdk::codes::kWriteFailed,
                 "cannot write '" + a.file + "': " + std::strerror(errno), kExitFailed);
  std::cerr << "exported " << store->definitions().size() << " definitions and "
            << store->rules(true).size() << " rules of " << store->path() << " to " << a.file
            << "\n";
  return kExitOk;
}

std::string read_input(const std::string& file) {
  if (file == "-") {
    std::stringstream s;
    s << std::cin.rdbuf();
    return s.str();
  }
  std::ifstream in(file);
  if (!in) throw sdk::Error(sdk::codes::kBadRequest, "cannot read '" + file + "'");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Verbatim restore: only into an empty store, so nothing stored can be replaced.
int restore_store(const LexiconArgs& a, const std::string& path, const std::string& text) {
  // Checked in memory first: the export's shape (import_jsonl) and every rule's template.
  naturalization::LexiconStore scratch(":memory:");
  std::istringstream check(text);
  scratch.import_jsonl(check);
  std::set<std::string> quarantined;  // flagged by the export: copied, and stay quarantined
  {
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
      const auto j = nlohmann::json::parse(line, nullptr, false);
      if (j.is_object() && j.contains("quarantined") && j.contains("id") && j["id"].is_string())
        quarantined.insert(j["id"].get<std::string>());
    }
  }
  for (const auto& r : scratch.rules(true)) {
    if (quarantined.count(r.id)) continue;
    try {
      (void)naturalization::rule_from_stored(r);
    } catch (const sdk::Error& e) {
      throw sdk::Error(sdk::codes::kBadRequest, a.file + ": rule " + r.id + ": " + e.what());
    }
  }
  naturalization::LexiconStore store(path);
  std::ostringstream existing;
  store.export_jsonl(existing);
  if (!existing.str().empty())
    return error("import", sdk::codes::kBadRequest,
                 "--restore copies into an empty store only, and '" + path +
                     "' is not empty; import without --restore to add the definitions",
                 kExitUsage);
  std::istringstream in(text);
  const std::size_t n = store.import_jsonl(in);  // one transaction, durable on return
  std::cout << "restored " << n << " lines (" << scratch.definitions().size() << " definitions, "
            << scratch.rules(true).size() << " rules) into " << path << "\n";
  return kExitOk;
}

/// Definitions replayed through induction, as a session's define does (without a world, so no
/// generalization); rule and weight(s) lines are not copied.
int import_definitions(const LexiconArgs& a, const kernel::Config& config,
                       const std::string& text) {
  std::vector<naturalization::DefineRequest> defs;
  std::size_t not_copied = 0, line_no = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      const auto j = nlohmann::json::parse(line);
      const std::string type = j.value("type", std::string("definition"));
      if (type == "rule" || type == "weights" || type == "weight" || type == "preload_failure") {
        ++not_copied;
        continue;
      }
      if (type != "definition") throw std::runtime_error("unknown type '" + type + "'");
      naturalization::DefineRequest d;
      d.head = j.at("head").get<std::string>();
      d.body = j.at("body").get<std::vector<std::string>>();
      d.user = j.value("author", std::string("import"));
      d.via = "import";
      defs.push_back(std::move(d));
    } catch (const std::exception& e) {
      throw sdk::Error(
          sdk::codes::kBadRequest,
          a.file + " line " + std::to_string(line_no) +
              ": expected a lexicon export or {\"head\",\"body\":[...],\"author\"}: " + e.what());
    }
  }
  naturalization::NaturalizeOptions options =
      naturalization::NaturalizeOptions::from_config(config);
  options.preload.clear();  // import exactly the file
  naturalization::Naturalizer naturalizer(
      std::shared_ptr<kernel::Runtime>(kernel::make_runtime(config)), options);
  std::set<std::tuple<std::string, std::vector<std::string>, std::string>> stored;
  for (const auto& d : naturalizer.store().definitions()) stored.emplace(d.head, d.body, d.author);
  std::size_t added = 0, skipped = 0, rules = 0;
  std::vector<std::string> failures;
  for (const auto& d : defs) {
    if (!stored.emplace(d.head, d.body, d.user).second) {
      ++skipped;
      continue;
    }
    try {
      const auto outcome = naturalizer.define(d);
      rules += outcome.rules.size();
      ++added;
      // Phrases of other users it reads differently (docs/naturalization.md §5 "Conflicts").
      for (const auto& c : outcome.conflicts)
        std::cout << "conflict: '" << d.head << "' (" << d.user << ") changes " << c.user << "'s '"
                  << c.phrase << "': " << c.kind << " " << (c.before.empty() ? "(none)" : c.before)
                  << " -> " << c.after << "\n";
    } catch (const sdk::Error& e) {
      if (naturalization::lexicon_codes::is_store_fault(e.code())) throw;
      failures.push_back("'" + d.head + "' (" + d.user + "): " + e.code() + ": " + e.what());
    }
  }
  std::cout << "imported " << added << " definitions (" << rules << " rules induced), " << skipped
            << " already stored, " << failures.size() << " failed, into "
            << naturalizer.store().path() << "\n";
  if (not_copied > 0)
    std::cout << not_copied
              << " rule/weights lines not copied: rules are induced from the definitions "
                 "(use --restore for a verbatim copy into an empty store)\n";
  for (const auto& f : failures) std::cerr << "flipper lexicon import: failed: " << f << "\n";
  return failures.empty() ? kExitOk : kExitFailed;
}

int import_store(const LexiconArgs& a) {
  const kernel::Config config = load_config(a.common);
  const std::string path = store_path(config);
  const std::string text = read_input(a.file);
  if (path == ":memory:")
    std::cerr << "flipper lexicon import: lexicon.path is :memory:, nothing will be kept\n";
  return a.restore ? restore_store(a, path, text) : import_definitions(a, config, text);
}

/// Deletes one rule as `--user`: the naturalizer checks authorship and keeps the history.
int delete_rule(const LexiconArgs& a) {
  const kernel::Config config = load_config(a.common);
  const std::string path = store_path(config);
  (void)open_existing(path);  // deleting never creates a store
  naturalization::NaturalizeOptions options =
      naturalization::NaturalizeOptions::from_config(config);
  options.preload.clear();
  naturalization::Naturalizer naturalizer(
      std::shared_ptr<kernel::Runtime>(kernel::make_runtime(config)), options);
  naturalizer.delete_rule(a.user, a.rule_id);
  std::cout << "deleted rule " << a.rule_id << " of " << a.user << " from "
            << naturalizer.store().path() << "\n";
  return kExitOk;
}

}  // namespace

void add_lexicon_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "lexicon",
      "List, export, import, delete, log, diff, tag, revert and moderate the community lexicon");
  cmd->require_subcommand(1);
  static LexiconArgs list_args, export_args, import_args;

  auto* list = cmd->add_subcommand("list", "List the live rules of the lexicon store");
  add_common_options(*list, list_args.common);
  list->add_option("--author", list_args.author, "Only the rules of this author");
  list->add_flag("--json", list_args.json, "Print the rules as one JSON object");
  on_run(*list, guarded("list", list_rules, list_args));

  auto* exp = cmd->add_subcommand("export", "Write the whole store as JSON Lines");
  add_common_options(*exp, export_args.common);
  exp->add_option("file", export_args.file, "Output file ('-': standard output)")->required();
  on_run(*exp, guarded("export", export_store, export_args));

  auto* imp = cmd->add_subcommand("import",
                                  "Add the definitions of a JSON Lines file, inducing their rules");
  add_common_options(*imp, import_args.common);
  imp->add_flag("--restore", import_args.restore,
                "Copy rules, counters and weights verbatim (into an empty store only)");
  imp->add_option("file", import_args.file, "Export or definitions file ('-': standard input)")
      ->required();
  on_run(*imp, guarded("import", import_store, import_args));

  static LexiconArgs delete_args;
  auto* del = cmd->add_subcommand("delete", "Delete a rule you defined (history is kept)");
  add_common_options(*del, delete_args.common);
  del->add_option("id", delete_args.rule_id, "The rule's id (from lexicon list)")->required();
  del->add_option("--user", delete_args.user, "Who deletes it: only its author may")->required();
  on_run(*del, guarded("delete", delete_rule, delete_args));

  add_lexicon_history_commands(*cmd);
  add_lexicon_moderation_commands(*cmd);
}

}  // namespace flipper::cli
