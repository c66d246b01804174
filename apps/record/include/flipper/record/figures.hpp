#pragma once
/// @file figures.hpp
/// A run's figures as tidy data (docs/experiments.md §3): one observation per row of
/// `figures.csv`, columns `variant,source,group,metric,value,unit,timing`. `source` says whose
/// figure it is (`ours`, or e.g. `original` for the logged study, `paper` for a published one),
/// `group` what it is about (a participant group, `all`, a world...), `timing` whether it
/// measures time (1) and so may differ between runs of the same inputs. Reports, plots, checks
/// and comparisons all read figures from here; `variants.csv` says what each variant is.

#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace flipper::record {

struct Figure {
  std::string variant, source, group, metric;
  double value = 0;
  std::string unit;  ///< "%", "ms", "queries", ... ("" for a plain number)
  bool timing = false;
};

/// The key that identifies a figure within a run.
using FigureKey = std::tuple<std::string, std::string, std::string, std::string>;
inline FigureKey key_of(const Figure& f) {
  return {f.variant, f.source, f.group, f.metric};
}

/// Writes figures.csv (values as exact_number, so a re-read gives the same doubles).
void write_figures(const std::string& path, const std::vector<Figure>& figures);
/// Reads figures.csv; throws sdk::Error(bad_request) naming the file and row.
std::vector<Figure> read_figures(const std::string& path);

/// Figures looked up by key; a missing figure is an error that names it (a report asking for a
/// figure nobody wrote is a bug, not a zero).
class FigureTable {
 public:
  FigureTable() = default;
  explicit FigureTable(const std::vector<Figure>& figures);
  double get(const std::string& variant, const std::string& source, const std::string& group,
             const std::string& metric) const;
  std::optional<double> find(const std::string& variant, const std::string& source,
                             const std::string& group, const std::string& metric) const;

 private:
  std::map<FigureKey, double> values_;
};

/// What a variant is: its name, the folder its files are in, its condition (the name without
/// its seed settings) and its seed settings ("" when it has none), and every setting it ran
/// with (experiment-wide first). `variants.csv` holds the first four, `settings.csv` the
/// settings one per row (`variant,key,value`).
struct VariantInfo {
  std::string name, directory, condition, seed;
  std::vector<std::pair<std::string, std::string>> settings;
};
void write_variants(const std::string& run_dir, const std::vector<VariantInfo>& variants);
std::vector<VariantInfo> read_variants(const std::string& run_dir);

/// Two runs' figures compared key by key. Deterministic figures that differ are `changed`;
/// timing figures that differ are `timing` (reported, never counted as differences).
struct FigureDiff {
  struct Change {
    FigureKey key;
    double a = 0, b = 0;
    std::string unit;
  };
  std::vector<Change> changed, timing;
  std::vector<FigureKey> only_a, only_b;
  std::size_t compared = 0;  ///< deterministic figures present in both
};
FigureDiff diff_figures(const std::vector<Figure>& a, const std::vector<Figure>& b);

/// One figure over the seeds of a condition: n, mean, sample standard deviation (0 for n = 1),
/// min and max.
struct Spread {
  std::string condition, source, group, metric, unit;
  bool timing = false;
  int n = 0;
  double mean = 0, sd = 0, min = 0, max = 0;
};
/// Groups the figures of variants that share a condition (variants.csv) and summarises each
/// figure over them, in the order conditions first appear.
std::vector<Spread> spread_over_seeds(const std::vector<Figure>& figures,
                                      const std::vector<VariantInfo>& variants);

/// "condition/source/group/metric" for messages.
std::string describe(const FigureKey& key);

}  // namespace flipper::record
