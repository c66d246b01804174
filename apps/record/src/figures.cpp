// figures.csv, variants.csv and settings.csv; figure differences and spread over seeds.
#include "flipper/record/figures.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

#include "flipper/record/csv.hpp"
#include "flipper/record/out_file.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::record {
namespace {

double parse_number(const std::string& text, const std::string& where) {
  double value = 0;
  const auto* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || text.empty())
    throw sdk::Error(sdk::codes::kBadRequest, where + ": '" + text + "' is not a number");
  return value;
}

}  // namespace

void write_figures(const std::string& path, const std::vector<Figure>& figures) {
  OutFile out(path);
  out << "variant,source,group,metric,value,unit,timing\n";
  for (const auto& f : figures)
    out << csv_line({f.variant, f.source, f.group, f.metric, exact_number(f.value), f.unit,
                     f.timing ? "1" : "0"})
        << "\n";
  out.close();
}

std::vector<Figure> read_figures(const std::string& path) {
  const CsvTable t = read_csv(path);
  const std::size_t variant = t.column("variant", path), source = t.column("source", path),
                    group = t.column("group", path), metric = t.column("metric", path),
                    value = t.column("value", path), unit = t.column("unit", path),
                    timing = t.column("timing", path);
  std::vector<Figure> out;
  out.reserve(t.rows.size());
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const auto& r = t.rows[i];
    const std::string where = path + ": row " + std::to_string(i + 1);
    out.push_back({r[variant], r[source], r[group], r[metric], parse_number(r[value], where),
                   r[unit], r[timing] == "1"});
  }
  return out;
}

FigureTable::FigureTable(const std::vector<Figure>& figures) {
  for (const auto& f : figures) values_[key_of(f)] = f.value;
}

std::optional<double> FigureTable::find(const std::string& variant, const std::string& source,
                                        const std::string& group, const std::string& metric) const {
  auto it = values_.find({variant, source, group, metric});
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

double FigureTable::get(const std::string& variant, const std::string& source,
                        const std::string& group, const std::string& metric) const {
  if (auto v = find(variant, source, group, metric)) return *v;
  throw sdk::Error(sdk::codes::kInternal,
                   "no figure " + describe({variant, source, group, metric}) + " in the run");
}

void write_variants(const std::string& run_dir, const std::vector<VariantInfo>& variants) {
  OutFile v(run_dir + "/variants.csv");
  v << "variant,directory,condition,seed\n";
  for (const auto& x : variants) v << csv_line({x.name, x.directory, x.condition, x.seed}) << "\n";
  v.close();
  OutFile s(run_dir + "/settings.csv");
  s << "variant,key,value\n";
  for (const auto& x : variants)
    for (const auto& [key, value] : x.settings) s << csv_line({x.name, key, value}) << "\n";
  s.close();
}

std::vector<VariantInfo> read_variants(const std::string& run_dir) {
  const std::string path = run_dir + "/variants.csv";
  const CsvTable t = read_csv(path);
  const std::size_t name = t.column("variant", path), dir = t.column("directory", path),
                    condition = t.column("condition", path), seed = t.column("seed", path);
  std::vector<VariantInfo> out;
  for (const auto& r : t.rows) out.push_back({r[name], r[dir], r[condition], r[seed], {}});
  const std::string settings_path = run_dir + "/settings.csv";
  const CsvTable s = read_csv(settings_path);
  const std::size_t sv = s.column("variant", settings_path), sk = s.column("key", settings_path),
                    sval = s.column("value", settings_path);
  for (const auto& r : s.rows)
    for (auto& v : out)
      if (v.name == r[sv]) v.settings.emplace_back(r[sk], r[sval]);
  return out;
}

FigureDiff diff_figures(const std::vector<Figure>& a, const std::vector<Figure>& b) {
  std::map<FigureKey, const Figure*> in_b;
  for (const auto& f : b) in_b[key_of(f)] = &f;
  std::set<FigureKey> seen;
  FigureDiff d;
  for (const auto& f : a) {
    const FigureKey k = key_of(f);
    seen.insert(k);
    auto it = in_b.find(k);
    if (it == in_b.end()) {
      d.only_a.push_back(k);
      continue;
    }
    const Figure& g = *it->second;
    const bool timing = f.timing || g.timing;
    if (!timing) ++d.compared;
    // Bitwise-equal values (both read from exact text): NaN never occurs in a figure.
    if (f.value == g.value) continue;
    (timing ? d.timing : d.changed).push_back({k, f.value, g.value, f.unit});
  }
  for (const auto& f : b)
    if (!seen.count(key_of(f))) d.only_b.push_back(key_of(f));
  return d;
}

std::vector<Spread> spread_over_seeds(const std::vector<Figure>& figures,
                                      const std::vector<VariantInfo>& variants) {
  std::map<std::string, std::string> condition_of;
  for (const auto& v : variants) condition_of[v.name] = v.condition;
  using Key = std::tuple<std::string, std::string, std::string, std::string>;
  std::map<Key, std::size_t> index;
  std::vector<Spread> out;
  std::vector<std::vector<double>> values;
  for (const auto& f : figures) {
    auto c = condition_of.find(f.variant);
    const std::string condition = c == condition_of.end() ? f.variant : c->second;
    const Key k{condition, f.source, f.group, f.metric};
    auto [it, fresh] = index.emplace(k, out.size());
    if (fresh) {
      out.push_back({condition, f.source, f.group, f.metric, f.unit, f.timing, 0, 0, 0, 0, 0});
      values.emplace_back();
    }
    values[it->second].push_back(f.value);
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    const auto& v = values[i];
    Spread& s = out[i];
    s.n = static_cast<int>(v.size());
    s.min = *std::min_element(v.begin(), v.end());
    s.max = *std::max_element(v.begin(), v.end());
    double sum = 0;
    for (double x : v) sum += x;
    s.mean = sum / static_cast<double>(v.size());
    double sq = 0;
    for (double x : v) sq += (x - s.mean) * (x - s.mean);
    s.sd = v.size() > 1 ? std::sqrt(sq / static_cast<double>(v.size() - 1)) : 0.0;
  }
  return out;
}

std::string describe(const FigureKey& key) {
  return std::get<0>(key) + "/" + std::get<1>(key) + "/" + std::get<2>(key) + "/" +
         std::get<3>(key);
}

}  // namespace flipper::record
