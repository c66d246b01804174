#pragma once
/// @file figures.hpp
/// A replay variant's figures as tidy rows (flipper/record/figures.hpp): every figure report.md
/// shows and the plots draw. Sources: `ours`, `original` (the study's logged outcomes on the same
/// split), `paper` (the published whole-study figures). Metric names: docs/experiments.md §3.

#include <string>
#include <vector>

#include "flipper/record/figures.hpp"
#include "flipper/replay/metrics.hpp"

namespace flipper::replay {

std::vector<record::Figure> replay_figures(const std::string& variant, const Metrics& m);

}  // namespace flipper::replay
