#pragma once
// Tour construction on a complete graph given by a symmetric distance matrix: Christofides
// (minimum spanning tree, greedy matching of odd-degree vertices, Euler circuit, shortcutting)
// and local improvement of an open path by 2-opt and Or-opt. Vertex numbers are the tie order:
// whenever two choices are equally good, the one with smaller vertex numbers wins, so the
// caller numbers vertices in (x, y, z) order to get the core language's tie rule. Independent of
// grids, so the benchmark's straight-line baseline uses the same code.
#include <functional>
#include <vector>

namespace flipper::plugins::astar {

/// Row-major n x n distances, symmetric, zero diagonal.
struct DistanceMatrix {
  int n = 0;
  std::vector<double> d;
  double operator()(int a, int b) const { return d[static_cast<std::size_t>(a) * n + b]; }
};

/// Christofides' Hamiltonian cycle from `start`: the visiting order, starting with `start`
/// (the closing edge back to `start` is implied).
std::vector<int> christofides_cycle(const DistanceMatrix& m, int start);

/// The better of the cycle's two directions as an open path from its first vertex (ties: the
/// cycle's own direction).
std::vector<int> open_path_from_cycle(const DistanceMatrix& m, const std::vector<int>& cycle);

/// Length of the open path `p` (sum over consecutive vertices).
double open_length(const DistanceMatrix& m, const std::vector<int>& p);

/// 2-opt (segment reversal) and, if `or_opt`, Or-opt (moving segments of 1-3 vertices, either
/// way round) on the open path `p` with p[0] fixed, until no move shortens it. 2-opt scans
/// every move; above 200 vertices Or-opt only tries insertion next to the 10 nearest neighbours
/// of the segment's ends. First improving move in scan order wins (deterministic). `should_stop` is
/// polled once per pass; returns false if it fired (p is then still a valid, partly improved path).
bool improve_open_path(const DistanceMatrix& m, std::vector<int>& p, bool two_opt, bool or_opt,
                       const std::function<bool()>& should_stop);

}  // namespace flipper::plugins::astar
