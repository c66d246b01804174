// report.md: what the run is (from its manifest), the variants side by side, then each variant's
// figures: ours | original on the same split | paper (whole study); agreement, execution,
// planner, latency, definitions. Every number comes from the run's figures (figures.csv).
#include <filesystem>

#include "flipper/corpus/accept_diff.hpp"
#include "flipper/record/compare.hpp"
#include "flipper/record/out_file.hpp"
#include "flipper/replay/output.hpp"

namespace flipper::replay {
namespace {

using nlohmann::json;
using record::FigureTable;

std::string text(const json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : "";
}

class VariantSection {
 public:
  VariantSection(std::ostream& o, const std::vector<record::Figure>& figures, const FigureTable& t,
                 const record::VariantInfo& v)
      : o_(o), figures_(figures), t_(t), v_(v) {}

  void write(const json& manifest_variant) {
    o_ << "## Variant `" << v_.name << "`\n\n";
    if (!v_.settings.empty()) {
      o_ << "Settings:";
      for (const auto& [key, value] : v_.settings) o_ << " `" << key << "=" << value << "`";
      o_ << "\n\n";
    }
    for (const auto& note : manifest_variant.value("notes", json::array()))
      o_ << "Note: " << note.get<std::string>() << "\n\n";
    const std::string& d = v_.directory;
    o_ << "Files: [metrics.json](" << d << "/metrics.json), [queries.csv](" << d
       << "/queries.csv), [participants.csv](" << d << "/participants.csv), [groups.csv](" << d
       << "/groups.csv), [accepts.csv](" << d << "/accepts.csv), [definitions.csv](" << d
       << "/definitions.csv)\n\n";
    tokens();
    commands();
    agreement();
    execution();
    latency();
    definitions();
  }

 private:
  std::string v(const std::string& source, const std::string& group, const std::string& metric,
                bool decimals = true) const {
    const auto x = t_.find(v_.name, source, group, metric);
    if (!x) return "–";
    return decimals ? one_decimal(*x) : record::show_value(*x);
  }
  std::string range(const std::string& source, const std::string& group,
                    const std::string& metric) const {
    if (!t_.find(v_.name, source, group, metric + "_mean")) return "–";
    return v(source, group, metric + "_mean") + " (" + v(source, group, metric + "_min") + "–" +
           v(source, group, metric + "_max") + ")";
  }
  std::string count(const std::string& group, const std::string& metric) const {
    return v("ours", group, metric, false);
  }

  void tokens() {
    const std::string& d = v_.directory;
    o_ << "### Tokens per participant (task queries of the authors' participants)\n\n"
       << "![tokens](" << d << "/tokens.svg)\n\n"
       << "| group | participants | successful: ours | successful: original | all | paper "
          "(whole study) successful / all |\n|---|---|---|---|---|---|\n";
    for (const char* g : {"A", "B", "C"})
      o_ << "| " << g << " | " << v("ours", g, "participants", false) << " | "
         << v("ours", g, "tokens_successful_mean") << " | "
         << v("original", g, "tokens_successful_mean") << " | " << v("ours", g, "tokens_all_mean")
         << " | " << v("paper", g, "tokens_successful_mean") << " / "
         << v("paper", g, "tokens_all_mean") << " |\n";
  }

  void commands() {
    const std::string& d = v_.directory;
    o_ << "\n### Induced vs core commands per participant: mean (min–max)\n\n"
       << "![induced vs core](" << d << "/induced_core.svg)\n\n"
       << "| group | induced: ours | induced: original | core: ours | core: original | paper "
          "induced / core |\n|---|---|---|---|---|---|\n";
    for (const char* g : {"B", "C"})
      o_ << "| " << g << " | " << range("ours", g, "induced") << " | "
         << range("original", g, "induced") << " | " << range("ours", g, "core") << " | "
         << range("original", g, "core") << " | " << v("paper", g, "induced_mean") << " / "
         << v("paper", g, "core_mean") << " |\n";
    o_ << "\n### Group C: induced commands using rules by others vs by self, per participant\n\n"
       << "![others vs self](" << d << "/others_self.svg)\n\n"
       << "| | ours | original | paper |\n|---|---|---|---|\n"
       << "| by others | " << range("ours", "C", "by_others") << " | "
       << range("original", "C", "by_others") << " | " << v("paper", "C", "by_others_mean")
       << " |\n| by self | " << range("ours", "C", "by_self") << " | "
       << range("original", "C", "by_self") << " | " << v("paper", "C", "by_self_mean") << " |\n";
  }

  void agreement() {
    o_ << "\n### Status agreement (every replayed query)\n\nOverall: " << count("all", "agree")
       << " / " << count("all", "queries") << " = " << v("ours", "all", "agreement")
       << " %. By group:";
    for (const char* g : {"A", "B", "C"})
      if (t_.find(v_.name, "ours", g, "queries"))
        o_ << " " << g << " " << count(g, "agree") << "/" << count(g, "queries") << " ("
           << v("ours", g, "agreement") << " %);";
    o_ << "\n\n| original \\ ours | core | induced | unparsable | error |\n|---|---|---|---|---|\n";
    for (const char* original : {"Core", "Induced", "Nothing"}) {
      o_ << "| " << original;
      for (const char* ours : {"core", "induced", "unparsable", "error"})
        o_ << " | " << count(std::string(original) + "->" + ours, "confusion");
      o_ << " |\n";
    }
  }

  void execution() {
    o_ << "\n### Accepts and execution agreement\n\nAccepts: " << count("all", "accepts")
       << "; accepted program among our candidates: " << count("all", "accepts_matched")
       << "; executed: " << count("all", "accepts_executed")
       << "; compared with the logged next world: " << count("all", "accepts_compared")
       << ".\n\n| robot position | held items | items on the floor | all three |\n"
          "|---|---|---|---|\n| "
       << count("all", "exec_robot_agree") << " | " << count("all", "exec_held_agree") << " | "
       << count("all", "exec_floor_agree") << " | " << count("all", "exec_all_agree") << " |\n";
    std::string not_executed;
    for (const auto& note : groups_of("not_executed"))
      not_executed += " " + note + ": " + count(note, "not_executed") + ";";
    if (!not_executed.empty()) o_ << "\nNot executed:" << not_executed << "\n";
    o_ << "\nWhy the worlds differ (" << count("all", "accepts_classified")
       << " classified accepts: compared, or failed with a known next world; "
          "flipper/corpus/accept_diff.hpp; `class` column of accepts.csv):\n\n"
       << "| class | accepts | explanation |\n|---|---|---|\n";
    const auto classes = groups_of("accept_class");
    for (corpus::AcceptClass c : corpus::all_classes()) {
      const std::string id = corpus::class_id(c);
      if (std::find(classes.begin(), classes.end(), id) != classes.end())
        o_ << "| `" << id << "` | " << count(id, "accept_class") << " | " << corpus::class_label(c)
           << " |\n";
    }
    for (const auto& id : classes)
      if (!corpus::class_from_id(id))
        o_ << "| `" << id << "` | " << count(id, "accept_class") << " | unknown class |\n";
    o_ << "\nUnexplained: " << count("all", "unexplained") << ".\n";
    o_ << "\n### Planner on the accepted programs\n\n" << planner_table(t_, {v_}) << "\n";
  }

  void latency() {
    const std::string& d = v_.directory;
    o_ << "\n### Latency per query\n\n![latency](" << d << "/latency.svg)\n\n"
       << "| | n | p50 | p90 | p99 | max |\n|---|---|---|---|---|---|\n";
    for (const auto& [source, label] :
         {std::pair<const char*, const char*>{"ours",
                                              "ours (`ms`: in-process parse + plan; timing)"},
          {"original", "original (`walltime_s`: logged server wall time)"}}) {
      // A structured binding is not captured by reference in clang 14 (C++20 allows it, clang 16
      // implements it): pass the source as a plain variable.
      const char* const from = source;
      auto ms = [&](const char* metric) {
        return duration_text(t_.find(v_.name, from, "all", metric).value_or(0));
      };
      o_ << "| " << label << " | " << v(source, "all", "latency_n", false) << " | "
         << ms("latency_p50") << " | " << ms("latency_p90") << " | " << ms("latency_p99") << " | "
         << ms("latency_max") << " |\n";
    }
  }

  void definitions() {
    o_ << "\n### Definitions and deletions\n\nPreloaded: " << count("all", "preloaded_ok") << " / "
       << count("all", "preloaded")
       << " defined. Users' definitions: " << count("all", "defines_ok") << " / "
       << count("all", "defines") << " accepted.";
    const auto errors = groups_of("define_errors");
    if (!errors.empty()) {
      o_ << " Refusals:";
      for (const auto& code : errors)
        o_ << " `" << code << "` " << count(code, "define_errors") << ";";
    }
    const auto matches = groups_of("rule_match");
    if (!matches.empty()) {
      o_ << " Induced rules against the original's logged rules (lhs -> rhs per definition):";
      for (const auto& m : matches) o_ << " " << m << " " << count(m, "rule_match") << ";";
    }
    o_ << " Deletions: " << count("all", "deletes")
       << ", mapped to a definition: " << count("all", "deletes_mapped")
       << ", our rules deleted: " << count("all", "rules_deleted") << ".\n\n";
  }

  // The groups a metric has for this variant, in the order figures.csv lists them.
  std::vector<std::string> groups_of(const std::string& metric) const {
    std::vector<std::string> out;
    for (const auto& f : figures_)
      if (f.variant == v_.name && f.source == "ours" && f.metric == metric) out.push_back(f.group);
    return out;
  }

  std::ostream& o_;
  const std::vector<record::Figure>& figures_;
  const FigureTable& t_;
  const record::VariantInfo& v_;
};

// A plugin from outside the build's plugin folder, and one that hides a same-named plugin.
std::string origin_note(const json& plugin) {
  const json origin = plugin.value("origin", json::object());
  std::string note;
  if (!origin.value("in_tree", true)) note += " (out of tree)";
  for (const auto& hidden : origin.value("shadows", json::array()))
    note += " **shadows `" + hidden.get<std::string>() + "`**";
  return note;
}

void provenance(std::ostream& o, const json& m) {
  const json b = m.value("build", json::object());
  const json e = m.value("experiment", json::object());
  o << "## Appendix: what this run is\n\n"
    << "| | |\n|---|---|\n"
    << "| flipper | " << text(b, "flipper") << " (plugin SDK " << text(b, "sdk") << ") |\n"
    << "| build | commit `" << text(b, "commit") << "` (`" << text(b, "describe")
    << "`), uncommitted changes: " << text(b, "dirty") << " (when built) |\n";
  if (m.contains("source")) {
    const json& s = m["source"];
    o << "| source tree | `" << text(s, "tree") << "`: commit `" << text(s, "commit")
      << "`, uncommitted changes: " << text(s, "dirty") << " (" << text(s, "read") << ") |\n";
  }
  std::string libraries;
  const json libs = b.value("libraries", json::object());
  for (auto it = libs.begin(); it != libs.end(); ++it)
    libraries += (libraries.empty() ? "" : ", ") + it.key() + " " + it.value().get<std::string>();
  if (!libraries.empty()) o << "| libraries | " << libraries << " |\n";
  o << "| date | " << text(m, "started") << " – " << text(m, "finished") << " (UTC) |\n";
  const json host = m.value("host", json::object());
  o << "| host | " << text(host, "name") << " (" << text(host, "system") << " "
    << text(host, "release") << ", " << host.value("cores", 0)
    << " cores); jobs: " << m.value("jobs", 1) << " |\n";
  std::string argv;
  for (const auto& a : m.value("command", json::object()).value("argv", json::array()))
    argv += (argv.empty() ? "" : " ") + a.get<std::string>();
  o << "| command | `" << argv << "` in `" << text(m.value("command", json::object()), "cwd")
    << "` |\n";
  if (m.contains("shard") && m["shard"].is_object())
    o << "| shard | " << m["shard"].value("index", 0) << " of " << m["shard"].value("count", 1)
      << " (counting from 0) |\n";
  if (m.contains("merged_from")) {
    o << "| merged from |";
    for (const auto& s : m["merged_from"]) o << " `" << text(s, "run") << "`";
    o << " |\n";
  }
  for (const auto& f : m.value("inputs", json::array()))
    o << "| " << text(f, "role") << " | `" << text(f, "path") << "` sha256 `" << text(f, "sha256")
      << "` |\n";
  const json corpus = m.value("corpus", json::object());
  o << "| corpus | `" << text(corpus, "path") << "`:";
  for (const auto& f : corpus.value("files", json::array()))
    o << " `" << text(f, "name") << "` sha256 `" << text(f, "sha256").substr(0, 16) << "…`;";
  o << " |\n";
  o << "| runs | " << (e.value("runs", json::array()).empty() ? "all" : e["runs"].dump())
    << "; max queries per run: " << e.value("max_queries", 0) << " (0: all) |\n\n";

  for (const auto& v : m.value("variants", json::array())) {
    o << "<details><summary>Variant <code>" << text(v, "name")
      << "</code>: plugins, seeds and effective config</summary>\n\n"
      << "| plugin | version | file | sha256 |\n|---|---|---|---|\n";
    for (const auto& p : v.value("plugins", json::array()))
      o << "| " << text(p, "section") << ": " << text(p, "name") << " | " << text(p, "version")
        << " | `" << text(p, "file") << "`" << origin_note(p) << " | `" << text(p, "sha256")
        << "` |\n";
    o << "\nSeeds: ";
    const json seeds = v.value("seeds", json::object());
    if (seeds.empty()) o << "none (no plugin of this variant takes a seed)";
    for (auto it = seeds.begin(); it != seeds.end(); ++it)
      o << "`" << it.key() << "=" << it.value().get<std::string>() << "` ";
    o << "\n\nEach run's mode keys (by group) come after these: "
      << v.value("mode_overrides", json::object()).dump() << "\n\n";
    const json config = v.value("config", json::object());
    o << "Effective config (`flipper config print`";
    if (!text(config, "base_dir").empty())
      o << "; relative paths from `" << text(config, "base_dir") << "`";
    o << "):\n\n```yaml\n" << text(config, "effective") << "```\n\n";
    for (const auto& f : config.value("files", json::array()))
      o << "- " << text(f, "role") << " `" << text(f, "path") << "` sha256 `" << text(f, "sha256")
        << "`\n";
    o << "\n</details>\n\n";
  }
}

}  // namespace

void write_report(const std::string& run_dir, const json& manifest,
                  const std::vector<record::VariantInfo>& variants,
                  const std::vector<record::Figure>& figures) {
  const FigureTable table(figures);
  record::OutFile file(run_dir + "/report.md");
  std::ostream& o = file.stream();
  const json e = manifest.value("experiment", json::object());
  o << "# " << text(e, "name") << "\n\n";
  const json failed = manifest.value("failed", json::array());
  if (!failed.empty()) {
    o << "## Variants that did not finish\n\nRun status: " << text(manifest, "status") << ". "
      << failed.size()
      << " variant(s) lost their process; their figures are missing below, every other "
         "variant's are complete (docs/experiments.md §4).\n\n"
      << "| variant | status | cause |\n|---|---|---|\n";
    for (const auto& f : failed)
      o << "| " << text(f, "variant") << " | " << text(f, "status") << " | " << text(f, "cause")
        << " |\n";
    o << "\n";
  }
  const std::string plots = text(manifest.value("plots", json::object()), "message");
  if (!plots.empty()) o << "Plots: " << plots << "\n\n";
  o << "Figures count `q` commands with phase `task` of participants with `in_authors_tables`, "
       "per participant (merged participant label); successful = status not "
       "Nothing/unparsable. \"original\" is the original server's logged status on the same "
       "split; \"paper\" is the whole-study figure (both studies, every run), for reference. "
       "Every figure is also in `figures.csv` (tidy: variant, source, group, metric, value, "
       "unit, timing).\n\n";
  if (variants.size() > 1) {
    o << "## Variants compared\n\n![variants](variants.svg)\n\n"
      << "Status agreement with the original by group; the original's Core queries we parse as "
         "core; the original's Nothing queries we give a reading (core or induced); queries "
         "whose top reading leaves words out (the `floating` parser); accepts whose program is "
         "our first / among our first three candidates (of the matched accepts: the ranking); "
         "tokens of successful commands and induced / core commands per participant (task "
         "queries).\n\n"
      << variants_table(table, variants) << "\n"
      << "### Planner on the accepted programs\n\n![planner](planner.svg)\n\n"
      << planner_table(table, variants) << "\n";
    const std::string seeds = seeds_table(figures, variants);
    if (!seeds.empty())
      o << "### Over seeds (mean ± sd (min–max) per condition)\n\n" << seeds << "\n";
  }
  const json manifest_variants = manifest.value("variants", json::array());
  for (const auto& v : variants) {
    json mv = json::object();
    for (const auto& x : manifest_variants)
      if (text(x, "name") == v.name) mv = x;
    VariantSection(o, figures, table, v).write(mv);
  }
  // Results first; what produced them (build, source, libraries, inputs, each variant's plugins
  // and effective config) in the appendix.
  provenance(o, manifest);
  file.close();
}

}  // namespace flipper::replay
