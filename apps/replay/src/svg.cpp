// A small SVG writer for grouped bar charts (no external tool), and the replay's figures.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "flipper/replay/output.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/svg/svg.hpp"
#include "out_file.hpp"

namespace flipper::kernel::replay {
namespace {

using kernel::svg::escape;  // shared with the world pictures (apps/svg)
using kernel::svg::num;

// A "nice" axis maximum: 1, 2 or 5 times a power of ten, at least v.
double nice_max(double v) {
  if (v <= 0) return 1;
  double p = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= v) return m * p;
  return 10 * p;
}

const char* kColors[] = {"#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3", "#937860"};

}  // namespace

// Tick labels: integers when the step is whole (counts), else one decimal.
std::string tick_text(double v, bool whole) {
  char buf[32];
  std::snprintf(buf, sizeof buf, whole ? "%.0f" : "%.1f", v);
  return buf;
}

// Approximate width of a label in the 12 px sans-serif font (for layout, not for typesetting).
// Counts are far below 2^53: the conversion is exact; spelled out for -Wconversion.
double as_double(std::size_t n) {
  return static_cast<double>(n);
}

double text_width(const std::string& s) {
  return 7.0 * static_cast<double>(s.size());
}

std::string render_svg(const BarChart& c) {
  const double width = std::max(
      480.0, 120.0 + 40.0 * as_double(c.categories.size()) * as_double(c.series.size() + 1));
  double vmax = 0;
  bool counts = true;  // every value a whole number: integer ticks
  for (std::size_t s = 0; s < c.values.size(); ++s)
    for (std::size_t k = 0; k < c.values[s].size(); ++k) {
      vmax = std::max(vmax, c.values[s][k]);
      counts = counts && c.values[s][k] == std::floor(c.values[s][k]);
      if (s < c.high.size() && k < c.high[s].size()) vmax = std::max(vmax, c.high[s][k]);
    }
  vmax = nice_max(vmax);
  // Five steps, fewer when counts would give fractional ticks (vmax 2 -> steps of 1).
  const int steps = counts && vmax < 5 ? std::max(1, static_cast<int>(vmax)) : 5;
  const bool whole_ticks = std::floor(vmax / steps) == vmax / steps;
  double widest = 0;
  for (int i = 0; i <= steps; ++i)
    widest = std::max(widest, text_width(tick_text(vmax * i / steps, whole_ticks)));
  // The y title sits left of the widest tick label, never on it.
  const double left = 34 + widest, right = 20, top = 40;
  // The legend wraps into rows that fit the width.
  std::vector<std::pair<double, int>> legend_at;  // x, row
  double lx = left;
  int rows = 1;
  for (const auto& name : c.series) {
    const double w = 16 + text_width(name) + 24;
    if (lx + w > width - right && lx > left) lx = left, ++rows;
    legend_at.emplace_back(lx, rows - 1);
    lx += w;
  }
  const double bottom = 40 + 20.0 * rows, height = 300 + bottom;
  const double plot_w = width - left - right, plot_h = height - top - bottom;
  auto y = [&](double v) { return top + plot_h * (1 - v / vmax); };

  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(width) << "\" height=\""
    << num(height) << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  o << "<text x=\"" << num(width / 2) << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">"
    << escape(c.title) << "</text>\n";
  // Axis, gridlines and tick labels.
  for (int i = 0; i <= steps; ++i) {
    const double v = vmax * i / steps, yy = y(v);
    o << "<line x1=\"" << num(left) << "\" x2=\"" << num(left + plot_w) << "\" y1=\"" << num(yy)
      << "\" y2=\"" << num(yy) << "\" stroke=\"#ddd\"/>\n";
    o << "<text x=\"" << num(left - 6) << "\" y=\"" << num(yy + 4) << "\" text-anchor=\"end\">"
      << tick_text(v, whole_ticks) << "</text>\n";
  }
  o << "<text transform=\"translate(16," << num(top + plot_h / 2)
    << ") rotate(-90)\" text-anchor=\"middle\">" << escape(c.y_label) << "</text>\n";
  const double cluster = plot_w / as_double(std::max<std::size_t>(1, c.categories.size()));
  const double bar = cluster / as_double(c.series.size() + 1);
  for (std::size_t k = 0; k < c.categories.size(); ++k) {
    const double x0 = left + cluster * as_double(k) + bar / 2;
    for (std::size_t s = 0; s < c.series.size(); ++s) {
      const double v = k < c.values[s].size() ? c.values[s][k] : 0;
      const double x = x0 + bar * as_double(s);
      o << "<rect x=\"" << num(x) << "\" y=\"" << num(y(v)) << "\" width=\"" << num(bar * 0.9)
        << "\" height=\"" << num(top + plot_h - y(v)) << "\" fill=\"" << kColors[s % 6]
        << "\"><title>" << escape(c.series[s]) << ", " << escape(c.categories[k]) << ": " << num(v)
        << "</title></rect>\n";
      if (s < c.low.size() && k < c.low[s].size()) {
        const double cx = x + bar * 0.45;
        o << "<line x1=\"" << num(cx) << "\" x2=\"" << num(cx) << "\" y1=\"" << num(y(c.low[s][k]))
          << "\" y2=\"" << num(y(c.high[s][k])) << "\" stroke=\"black\"/>\n";
      }
    }
    o << "<text x=\"" << num(left + cluster * (as_double(k) + 0.5)) << "\" y=\""
      << num(top + plot_h + 16) << "\" text-anchor=\"middle\">" << escape(c.categories[k])
      << "</text>\n";
  }
  o << "<line x1=\"" << num(left) << "\" x2=\"" << num(left + plot_w) << "\" y1=\""
    << num(top + plot_h) << "\" y2=\"" << num(top + plot_h) << "\" stroke=\"black\"/>\n";
  // Legend below the axis, wrapped into rows.
  for (std::size_t s = 0; s < c.series.size(); ++s) {
    const double x = legend_at[s].first, ly = top + plot_h + 44 + 20.0 * legend_at[s].second;
    o << "<rect x=\"" << num(x) << "\" y=\"" << num(ly - 10)
      << "\" width=\"12\" height=\"12\" fill=\"" << kColors[s % 6] << "\"/><text x=\""
      << num(x + 16) << "\" y=\"" << num(ly) << "\">" << escape(c.series[s]) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

namespace {

void save(const std::string& dir, const std::string& name, const BarChart& c) {
  OutFile out(dir + "/" + name);
  out << render_svg(c);
  out.close();
}

double mean_of(const std::map<std::string, Summary>& m, const std::string& g) {
  auto it = m.find(g);
  return it == m.end() ? 0 : it->second.mean;
}

}  // namespace

void write_figures(const std::string& dir, const Metrics& m) {
  std::filesystem::create_directories(dir);
  BarChart tokens{"Tokens per participant (task queries)",
                  "tokens",
                  {"A", "B", "C"},
                  {"successful (original)", "successful (ours)", "all (original)", "all (ours)"},
                  {},
                  {},
                  {}};
  for (const auto* side : {&m.original.tokens_successful, &m.ours.tokens_successful,
                           &m.original.tokens_all, &m.ours.tokens_all}) {
    std::vector<double> row;
    for (const auto& g : tokens.categories) row.push_back(mean_of(*side, g));
    tokens.values.push_back(row);
  }
  save(dir, "tokens.svg", tokens);

  BarChart ic{"Induced vs core commands per participant (mean, min-max)",
              "commands",
              {"B", "C"},
              {"induced (original)", "induced (ours)", "core (original)", "core (ours)"},
              {},
              {},
              {}};
  for (const auto* side : {&m.original.induced, &m.ours.induced, &m.original.core, &m.ours.core}) {
    std::vector<double> v, lo, hi;
    for (const auto& g : ic.categories) {
      auto it = side->find(g);
      Summary s = it == side->end() ? Summary{} : it->second;
      v.push_back(s.mean);
      lo.push_back(s.min);
      hi.push_back(s.max);
    }
    ic.values.push_back(v);
    ic.low.push_back(lo);
    ic.high.push_back(hi);
  }
  save(dir, "induced_core.svg", ic);

  BarChart os{
      "Group C: induced commands using rules by others vs by self",
      "commands per participant",
      {"others", "self"},
      {"original", "ours"},
      {{m.original.others.mean, m.original.self.mean}, {m.ours.others.mean, m.ours.self.mean}},
      {{m.original.others.min, m.original.self.min}, {m.ours.others.min, m.ours.self.min}},
      {{m.original.others.max, m.original.self.max}, {m.ours.others.max, m.ours.self.max}}};
  save(dir, "others_self.svg", os);

  // The two series measure different things, and say so: the original's logged server wall
  // time per query vs our in-process parse + plan time (the answer's `ms`).
  BarChart lat{"Query latency (log-scale bins, ms; different measures)",
               "queries",
               {},
               {"original: logged server wall time", "ours: in-process parse + plan"},
               {{}, {}},
               {},
               {}};
  const auto& edges = latency_bins();
  // Only the occupied range of bins.
  std::size_t first = edges.size(), last = 0;
  for (std::size_t i = 0; i + 1 < edges.size(); ++i)
    if (m.original_latency.histogram[i] + m.our_latency.histogram[i] > 0)
      first = std::min(first, i), last = i;
  for (std::size_t i = first; i <= last && i + 1 < edges.size(); ++i) {
    char label[48];
    std::snprintf(label, sizeof label, "%g",
                  edges[i] < 1 ? std::round(edges[i] * 1000) / 1000 : std::round(edges[i]));
    lat.categories.push_back(std::string(label) + "+");
    lat.values[0].push_back(m.original_latency.histogram[i]);
    lat.values[1].push_back(m.our_latency.histogram[i]);
  }
  save(dir, "latency.svg", lat);
}

}  // namespace flipper::kernel::replay
