// The cross-variant comparison of an experiment (ablations such as parser x scorer): one SVG
// with a panel per measure and one bar per variant, and the report section around it.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "flipper/replay/output.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::kernel::replay {
namespace {

std::string f1(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

double mean_of(const std::map<std::string, Summary>& m, const std::string& g) {
  auto it = m.find(g);
  return it == m.end() ? 0 : it->second.mean;
}

double group_rate(const Metrics& m, const std::string& g) {
  auto it = m.by_group.find(g);
  return it == m.by_group.end() ? 0 : it->second.rate();
}

int confusion(const Metrics& m, const std::string& original, const std::string& ours) {
  auto row = m.overall.confusion.find(original);
  if (row == m.overall.confusion.end()) return 0;
  auto it = row->second.find(ours);
  return it == row->second.end() ? 0 : it->second;
}

int row_total(const Metrics& m, const std::string& original) {
  int n = 0;
  if (auto row = m.overall.confusion.find(original); row != m.overall.confusion.end())
    for (const auto& [ours, k] : row->second) n += k;
  return n;
}

// The numeric value of attribute `name` in the first tag of an SVG document.
double attribute(const std::string& svg, const std::string& name) {
  const auto at = svg.find(" " + name + "=\"");
  if (at == std::string::npos) return 0;
  return std::stod(svg.substr(at + name.size() + 3));
}

// Panels stacked vertically into one SVG document (nested <svg> elements at y offsets).
std::string stack(const std::vector<std::string>& panels) {
  double width = 0, height = 0;
  for (const auto& p : panels) {
    width = std::max(width, attribute(p, "width"));
    height += attribute(p, "height");
  }
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << f1(width) << "\" height=\""
    << f1(height) << "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  double y = 0;
  for (const auto& p : panels) {
    std::string inner = p;
    inner.replace(0, 4, "<svg x=\"0\" y=\"" + f1(y) + "\"");  // "<svg" + placement
    o << inner;
    y += attribute(p, "height");
  }
  o << "</svg>\n";
  return o.str();
}

std::vector<std::string> names(const std::vector<Variant>& variants) {
  std::vector<std::string> out;
  out.reserve(variants.size());
  for (const auto& v : variants) out.push_back(v.name);
  return out;
}

}  // namespace

void write_variant_figure(const std::string& dir, const std::vector<Variant>& variants) {
  std::filesystem::create_directories(dir);
  // Percentages share one panel: status agreement by group, then how often the accepted program
  // (of the matched accepts) was our first / among our first three candidates.
  BarChart percent{"Status agreement with the original; rank of the accepted program",
                   "%",
                   {"agree A", "agree B", "agree C", "agree all", "accepted 1st", "accepted top 3"},
                   names(variants),
                   {},
                   {},
                   {}};
  BarChart tokens{"Tokens of successful commands per participant (task queries)",
                  "tokens",
                  {"A", "B", "C"},
                  names(variants),
                  {},
                  {},
                  {}};
  BarChart commands{"Induced vs core commands per participant (task queries)",
                    "commands",
                    {"induced B", "induced C", "core B", "core C"},
                    names(variants),
                    {},
                    {},
                    {}};
  for (const auto& v : variants) {
    const Metrics& m = v.metrics;
    const double matched = std::max(1, m.exec.matched);
    percent.values.push_back({100 * group_rate(m, "A"), 100 * group_rate(m, "B"),
                              100 * group_rate(m, "C"), 100 * m.overall.rate(),
                              100 * m.accepted_top1 / matched, 100 * m.accepted_top3 / matched});
    tokens.values.push_back({mean_of(m.ours.tokens_successful, "A"),
                             mean_of(m.ours.tokens_successful, "B"),
                             mean_of(m.ours.tokens_successful, "C")});
    commands.values.push_back({mean_of(m.ours.induced, "B"), mean_of(m.ours.induced, "C"),
                               mean_of(m.ours.core, "B"), mean_of(m.ours.core, "C")});
  }
  const std::string path = dir + "/variants.svg";
  std::ofstream out(path);
  out << stack({render_svg(percent), render_svg(tokens), render_svg(commands)});
  if (!out) throw sdk::Error(sdk::codes::kBadRequest, "cannot write '" + path + "'");
}

void write_variant_section(std::ostream& o, const std::vector<Variant>& variants) {
  o << "## Variants compared\n\n![variants](variants.svg)\n\n"
    << "Status agreement with the original by group; the original's Core queries we parse as "
       "core; the original's Nothing queries we give a reading (core or induced); queries whose "
       "top reading leaves words out (the `floating` parser); accepts whose program is our "
       "first / among our first three candidates (of the matched accepts: the ranking); tokens "
       "of successful commands and induced / core commands per participant (task queries).\n\n"
    << "| variant | agreement all / A / B / C | Core → core | Nothing → reading | floating "
       "tops | accepted: first / top 3 / matched | tokens succ. A / B / C | induced B / C | core "
       "B / C |\n"
    << "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& v : variants) {
    const Metrics& m = v.metrics;
    o << "| " << v.name << " | " << f1(100 * m.overall.rate()) << " / "
      << f1(100 * group_rate(m, "A")) << " / " << f1(100 * group_rate(m, "B")) << " / "
      << f1(100 * group_rate(m, "C")) << " % | " << confusion(m, "Core", "core") << " / "
      << row_total(m, "Core") << " | "
      << confusion(m, "Nothing", "core") + confusion(m, "Nothing", "induced") << " / "
      << row_total(m, "Nothing") << " | " << m.floating << " | " << m.accepted_top1 << " / "
      << m.accepted_top3 << " / " << m.exec.matched << " | "
      << f1(mean_of(m.ours.tokens_successful, "A")) << " / "
      << f1(mean_of(m.ours.tokens_successful, "B")) << " / "
      << f1(mean_of(m.ours.tokens_successful, "C")) << " | " << f1(mean_of(m.ours.induced, "B"))
      << " / " << f1(mean_of(m.ours.induced, "C")) << " | " << f1(mean_of(m.ours.core, "B"))
      << " / " << f1(mean_of(m.ours.core, "C")) << " |\n";
  }
  o << "\n";
}

}  // namespace flipper::kernel::replay
