#pragma once
/// @file plots.hpp
/// Drawing a run's plots (docs/experiments.md §5): the plot scripts live in the repository
/// (apps/plots/*.py), are installed to <prefix>/share/flipper/plots and found relative to the
/// flipper binary (<exe>/../share/flipper/plots; the build tree links it to apps/plots). They
/// read only the run's CSV files and write PDF, SVG and, beside each figure, the data and labels
/// it plotted (<figure>.plotdata.json). Python with matplotlib is optional: without it the run
/// succeeds and says how to get the plots.

#include <map>
#include <string>

namespace flipper::record {

struct PlotOutcome {
  enum class Status { drawn, skipped, failed } status = Status::skipped;
  std::string message;  ///< what was drawn, why skipped (and how to get them), or the error
  /// When drawn: {"python" (the interpreter), "python_version", "matplotlib"}.
  std::map<std::string, std::string> versions;
};

/// The installed plot scripts' folder (<exe>/../share/flipper/plots, resolved through links),
/// or "" when there is none.
std::string plots_dir();

/// Runs `script` (a file name in plots_dir()) on `run_dir` with the first Python that has
/// matplotlib: $FLIPPER_PYTHON, else `python3` on the PATH, else /usr/bin/python3 (Debian's,
/// where python3-matplotlib installs). Never throws for a missing Python or matplotlib.
PlotOutcome draw_plots(const std::string& script, const std::string& run_dir);

}  // namespace flipper::record
