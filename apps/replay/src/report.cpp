// report.md: the figures (ours | original on the same split | paper, whole study), agreement,
// execution, latency, definitions; variants side by side.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "flipper/corpus/accept_diff.hpp"
#include "flipper/replay/output.hpp"
#include "flipper/sdk/errors.hpp"
#include "out_file.hpp"

namespace flipper::kernel::replay {
namespace {

std::string f1(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}
std::string pct(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f %%", 100 * v);
  return b;
}
double mean_of(const std::map<std::string, Summary>& m, const std::string& g) {
  auto it = m.find(g);
  return it == m.end() ? 0 : it->second.mean;
}
std::string range(const std::map<std::string, Summary>& m, const std::string& g) {
  auto it = m.find(g);
  if (it == m.end()) return "–";
  return f1(it->second.mean) + " (" + f1(it->second.min) + "–" + f1(it->second.max) + ")";
}
std::string range(const Summary& s) {
  return f1(s.mean) + " (" + f1(s.min) + "–" + f1(s.max) + ")";
}

// The paper's whole-study figures (both studies, all runs), for reference only.
struct Paper {
  const char* group;
  double successful, all;
};
constexpr Paper kPaperTokens[] = {{"A", 1150, 1586}, {"B", 585, 831}, {"C", 487, 670}};

void variant_section(std::ostream& o, const Variant& v) {
  const Metrics& m = v.metrics;
  o << "## Variant `" << v.name << "`\n\n";
  if (!v.sets.empty()) {
    o << "Settings:";
    for (const auto& s : v.sets) o << " `" << s << "`";
    o << "\n\n";
  }
  o << "Files: [metrics.json](" << v.dir << "/metrics.json), [queries.csv](" << v.dir
    << "/queries.csv), [participants.csv](" << v.dir << "/participants.csv), [groups.csv](" << v.dir
    << "/groups.csv), [accepts.csv](" << v.dir << "/accepts.csv)\n\n";

  o << "### Tokens per participant (task queries of the authors' participants)\n\n"
    << "![tokens](" << v.dir << "/tokens.svg)\n\n"
    << "| group | participants | successful: ours | successful: original | all | paper (whole "
       "study) successful / all |\n"
    << "|---|---|---|---|---|---|\n";
  for (const auto& p : kPaperTokens) {
    auto it = m.ours.tokens_all.find(p.group);
    o << "| " << p.group << " | " << (it == m.ours.tokens_all.end() ? 0 : it->second.n) << " | "
      << f1(mean_of(m.ours.tokens_successful, p.group)) << " | "
      << f1(mean_of(m.original.tokens_successful, p.group)) << " | "
      << f1(mean_of(m.ours.tokens_all, p.group)) << " | " << p.successful << " / " << p.all
      << " |\n";
  }
  o << "\n### Induced vs core commands per participant: mean (min–max)\n\n"
    << "![induced vs core](" << v.dir << "/induced_core.svg)\n\n"
    << "| group | induced: ours | induced: original | core: ours | core: original | paper induced "
       "/ core |\n"
    << "|---|---|---|---|---|---|\n";
  o << "| B | " << range(m.ours.induced, "B") << " | " << range(m.original.induced, "B") << " | "
    << range(m.ours.core, "B") << " | " << range(m.original.core, "B") << " | 54.6 / 72.9 |\n";
  o << "| C | " << range(m.ours.induced, "C") << " | " << range(m.original.induced, "C") << " | "
    << range(m.ours.core, "C") << " | " << range(m.original.core, "C") << " | 51.8 / 54.3 |\n";
  o << "\n### Group C: induced commands using rules by others vs by self, per participant\n\n"
    << "![others vs self](" << v.dir << "/others_self.svg)\n\n"
    << "| | ours | original | paper |\n|---|---|---|---|\n"
    << "| by others | " << range(m.ours.others) << " | " << range(m.original.others)
    << " | 37.2 |\n"
    << "| by self | " << range(m.ours.self) << " | " << range(m.original.self) << " | 14.6 |\n";

  o << "\n### Status agreement (every replayed query)\n\n"
    << "Overall: " << m.overall.agree << " / " << m.overall.n << " = " << pct(m.overall.rate())
    << ". By group:";
  for (const auto& [g, a] : m.by_group)
    o << " " << g << " " << a.agree << "/" << a.n << " (" << pct(a.rate()) << ");";
  o << "\n\n| original \\ ours | core | induced | unparsable | error |\n|---|---|---|---|---|\n";
  for (const char* orig : {"Core", "Induced", "Nothing"}) {
    o << "| " << orig;
    auto row = m.overall.confusion.find(orig);
    for (const char* ours : {"core", "induced", "unparsable", "error"}) {
      int n = 0;
      if (row != m.overall.confusion.end()) {
        auto it = row->second.find(ours);
        if (it != row->second.end()) n = it->second;
      }
      o << " | " << n;
    }
    o << " |\n";
  }
  const auto& e = m.exec;
  o << "\n### Accepts and execution agreement\n\n"
    << "Accepts: " << e.accepts << "; accepted program among our candidates: " << e.matched
    << "; executed: " << e.executed << "; compared with the logged next world: " << e.compared
    << ".\n\n| robot position | held items | items on the floor | all three |\n|---|---|---|---|\n"
    << "| " << e.robot << " | " << e.held << " | " << e.floor << " | " << e.all << " |\n";
  if (!e.not_executed.empty()) {
    o << "\nNot executed:";
    for (const auto& [note, n] : e.not_executed) o << " " << note << ": " << n << ";";
    o << "\n";
  }
  o << "\nWhy the worlds differ (" << e.classified
    << " classified accepts: compared, or failed with a known next world; "
       "flipper/corpus/accept_diff.hpp; `class` column of accepts.csv):\n\n"
    << "| class | accepts | explanation |\n|---|---|---|\n";
  for (corpus::AcceptClass c : corpus::all_classes()) {
    auto it = e.classes.find(corpus::class_id(c));
    if (it != e.classes.end())
      o << "| `" << it->first << "` | " << it->second << " | " << corpus::class_label(c) << " |\n";
  }
  for (const auto& [id, n] : e.classes)
    if (!corpus::class_from_id(id)) o << "| `" << id << "` | " << n << " | unknown class |\n";
  o << "\nUnexplained: " << e.unexplained << ".\n";
  o << "\n### Latency (ms per query)\n\n![latency](" << v.dir << "/latency.svg)\n\n"
    << "| | n | p50 | p90 | p99 | max |\n|---|---|---|---|---|---|\n";
  for (const auto& [name, l] :
       {std::pair<const char*, const Latency*>{"ours (`ms`)", &m.our_latency},
        {"original (`walltime_s`)", &m.original_latency}})
    o << "| " << name << " | " << l->summary.n << " | " << f1(l->p50) << " | " << f1(l->p90)
      << " | " << f1(l->p99) << " | " << f1(l->summary.max) << " |\n";
  o << "\n### Definitions and deletions\n\n"
    << "Preloaded: " << m.preloaded_ok << " / " << m.preloaded
    << " defined. Users' definitions: " << m.defines_ok << " / " << m.defines << " accepted.";
  if (!m.define_errors.empty()) {
    o << " Refusals:";
    for (const auto& [code, n] : m.define_errors) o << " `" << code << "` " << n << ";";
  }
  if (!m.rule_match.empty()) {
    o << " Induced rules against the original's logged rules (lhs -> rhs per definition):";
    for (const auto& [match, n] : m.rule_match) o << " " << match << " " << n << ";";
  }
  o << " Deletions: " << m.deletes << ", mapped to a definition: " << m.deletes_mapped
    << ", our rules deleted: " << m.rules_deleted << ".\n\n";
}

}  // namespace

void write_report(const std::string& dir, const std::string& title,
                  const std::vector<Variant>& variants, const std::string& corpus,
                  const std::vector<std::string>& runs) {
  std::filesystem::create_directories(dir);
  OutFile file(dir + "/report.md");
  std::ostream& o = file.stream();
  o << "# " << title << "\n\nCorpus: `" << corpus << "`. Runs:";
  for (const auto& r : runs) o << " `" << r << "`";
  o << ".\n\nFigures count `q` commands with phase `task` of participants with "
       "`in_authors_tables`, per participant (merged participant label); successful = status "
       "not Nothing/unparsable. \"original\" is the original server's logged status on the same "
       "split; \"paper\" is the whole-study figure (both studies, every run), for reference.\n\n";
  if (variants.size() > 1) {
    o << "## Variants side by side\n\n| variant | agreement | tokens succ. A/B/C | induced B/C | "
         "core B/C | C others/self | accepts matched | exec all-agree | p50 ms | p99 ms |\n"
         "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& v : variants) {
      const Metrics& m = v.metrics;
      o << "| " << v.name << " | " << pct(m.overall.rate()) << " | "
        << f1(mean_of(m.ours.tokens_successful, "A")) << " / "
        << f1(mean_of(m.ours.tokens_successful, "B")) << " / "
        << f1(mean_of(m.ours.tokens_successful, "C")) << " | " << f1(mean_of(m.ours.induced, "B"))
        << " / " << f1(mean_of(m.ours.induced, "C")) << " | " << f1(mean_of(m.ours.core, "B"))
        << " / " << f1(mean_of(m.ours.core, "C")) << " | " << f1(m.ours.others.mean) << " / "
        << f1(m.ours.self.mean) << " | " << m.exec.matched << "/" << m.exec.accepts << " | "
        << m.exec.all << "/" << m.exec.compared << " | " << f1(m.our_latency.p50) << " | "
        << f1(m.our_latency.p99) << " |\n";
    }
    o << "\n";
    write_variant_section(o, variants);
  }
  for (const auto& v : variants) variant_section(o, v);
  file.close();
}

}  // namespace flipper::kernel::replay
