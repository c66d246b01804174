#include "tour_solver.hpp"

#include <algorithm>
#include <limits>
#include <tuple>

namespace flipper::plugins::astar {
namespace {

constexpr double kEps = 1e-9;

// Prim's algorithm on the dense matrix, O(n^2). Ties: the smaller vertex joins first, and a
// vertex keeps the smaller-numbered parent among equally near tree vertices.
std::vector<std::pair<int, int>> minimum_spanning_tree(const DistanceMatrix& m, int root) {
  const int n = m.n;
  std::vector<double> key(n, std::numeric_limits<double>::infinity());
  std::vector<int> parent(n, -1);
  std::vector<char> in_tree(n, 0);
  std::vector<std::pair<int, int>> edges;
  edges.reserve(n > 0 ? n - 1 : 0);
  key[root] = 0;
  for (int step = 0; step < n; ++step) {
    int u = -1;
    for (int v = 0; v < n; ++v)
      if (!in_tree[v] && (u < 0 || key[v] < key[u] - kEps)) u = v;
    in_tree[u] = 1;
    if (parent[u] >= 0) edges.emplace_back(parent[u], u);
    for (int v = 0; v < n; ++v) {
      if (in_tree[v]) continue;
      const double w = m(u, v);
      if (w < key[v] - kEps || (w < key[v] + kEps && u < parent[v])) {
        key[v] = w;
        parent[v] = u;
      }
    }
  }
  return edges;
}

// Greedy minimum perfect matching: cheapest pairs first, ties by (smaller, larger) vertex.
std::vector<std::pair<int, int>> greedy_matching(const DistanceMatrix& m,
                                                 const std::vector<int>& odd) {
  std::vector<std::tuple<double, int, int>> pairs;
  pairs.reserve(odd.size() * (odd.size() - (odd.empty() ? 0 : 1)) / 2);
  for (std::size_t a = 0; a < odd.size(); ++a)
    for (std::size_t b = a + 1; b < odd.size(); ++b)
      pairs.emplace_back(m(odd[a], odd[b]), odd[a], odd[b]);
  std::sort(pairs.begin(), pairs.end());
  std::vector<char> matched(m.n, 0);
  std::vector<std::pair<int, int>> out;
  for (const auto& [w, a, b] : pairs) {
    if (matched[a] || matched[b]) continue;
    matched[a] = matched[b] = 1;
    out.emplace_back(a, b);
  }
  return out;
}

// Hierholzer's algorithm; from each vertex the unused edge to the smallest neighbour is taken.
std::vector<int> euler_circuit(int n, const std::vector<std::pair<int, int>>& edges, int start) {
  std::vector<std::vector<std::pair<int, int>>> adj(n);  // (neighbour, edge id)
  for (int e = 0; e < static_cast<int>(edges.size()); ++e) {
    adj[edges[e].first].emplace_back(edges[e].second, e);
    adj[edges[e].second].emplace_back(edges[e].first, e);
  }
  for (auto& a : adj) std::sort(a.begin(), a.end());
  std::vector<char> used(edges.size(), 0);
  std::vector<std::size_t> next(n, 0);
  std::vector<int> stack{start}, circuit;
  while (!stack.empty()) {
    const int v = stack.back();
    auto& a = adj[v];
    while (next[v] < a.size() && used[a[next[v]].second]) ++next[v];
    if (next[v] < a.size()) {  // an unused edge: walk it
      used[a[next[v]].second] = 1;
      stack.push_back(a[next[v]].first);
      continue;
    }
    circuit.push_back(v);  // a dead end: it closes the circuit
    stack.pop_back();
  }
  std::reverse(circuit.begin(), circuit.end());
  return circuit;
}

}  // namespace

std::vector<int> christofides_cycle(const DistanceMatrix& m, int start) {
  if (m.n <= 2) {
    std::vector<int> p{start};
    for (int v = 0; v < m.n; ++v)
      if (v != start) p.push_back(v);
    return p;
  }
  auto edges = minimum_spanning_tree(m, start);
  std::vector<int> degree(m.n, 0);
  for (const auto& [a, b] : edges) ++degree[a], ++degree[b];
  std::vector<int> odd;
  for (int v = 0; v < m.n; ++v)
    if (degree[v] % 2 == 1) odd.push_back(v);
  for (const auto& e : greedy_matching(m, odd)) edges.push_back(e);
  std::vector<char> seen(m.n, 0);
  std::vector<int> cycle;
  cycle.reserve(m.n);
  for (int v : euler_circuit(m.n, edges, start))
    if (!seen[v]) {
      seen[v] = 1;
      cycle.push_back(v);
    }
  return cycle;
}

std::vector<int> open_path_from_cycle(const DistanceMatrix& m, const std::vector<int>& cycle) {
  if (cycle.size() <= 2) return cycle;
  std::vector<int> reversed{cycle.front()};
  reversed.insert(reversed.end(), cycle.rbegin(), cycle.rend() - 1);
  return open_length(m, reversed) < open_length(m, cycle) - kEps ? reversed : cycle;
}

double open_length(const DistanceMatrix& m, const std::vector<int>& p) {
  double total = 0;
  for (std::size_t i = 1; i < p.size(); ++i) total += m(p[i - 1], p[i]);
  return total;
}

namespace {

// Path edge lengths: e[k] = m(p[k], p[k+1]).
void edge_lengths(const DistanceMatrix& m, const std::vector<int>& p, std::vector<double>& e) {
  e.resize(p.size());
  for (std::size_t k = 0; k + 1 < p.size(); ++k) e[k] = m(p[k], p[k + 1]);
}

// One sweep of improving 2-opt moves (reverse p[i..j]); false if there is none. The matrix is
// symmetric, so every lookup is made along a row (m(x, y) == m(y, x) exactly) and the old edges
// come from the edge array: same values, same arithmetic, a fraction of the cache misses.
bool two_opt_pass(const DistanceMatrix& m, std::vector<int>& p, std::vector<double>& e) {
  const int len = static_cast<int>(p.size());
  bool improved = false;
  edge_lengths(m, p, e);
  for (int i = 1; i + 1 < len; ++i) {
    const int a = p[i - 1];
    const double* row_a = &m.d[static_cast<std::size_t>(a) * m.n];
    for (int j = i + 1; j < len; ++j) {
      const int b = p[i], c = p[j];
      const double* row_b = &m.d[static_cast<std::size_t>(b) * m.n];
      double delta = row_a[c] - e[i - 1];
      if (j + 1 < len) delta += row_b[p[j + 1]] - e[j];
      if (delta < -kEps) {
        std::reverse(p.begin() + i, p.begin() + j + 1);
        edge_lengths(m, p, e);
        improved = true;
      }
    }
  }
  return improved;
}

// Above this many vertices Or-opt only tries insertion points next to the kNeighbours nearest
// vertices of the segment's ends (a full scan is cubic per sweep there); 2-opt always scans all.
constexpr int kFullScanLimit = 200;
constexpr int kNeighbours = 10;

// The kNeighbours nearest other vertices of each vertex (ties: smaller vertex).
std::vector<std::vector<int>> nearest_neighbours(const DistanceMatrix& m) {
  std::vector<std::vector<int>> out(m.n);
  std::vector<int> others;
  for (int v = 0; v < m.n; ++v) {
    others.clear();
    for (int u = 0; u < m.n; ++u)
      if (u != v) others.push_back(u);
    const int k = std::min<int>(kNeighbours, static_cast<int>(others.size()));
    std::partial_sort(others.begin(), others.begin() + k, others.end(), [&](int a, int b) {
      return m(v, a) < m(v, b) || (m(v, a) == m(v, b) && a < b);
    });
    out[v].assign(others.begin(), others.begin() + k);
  }
  return out;
}

// One sweep of Or-opt moves: a segment p[i..i+len-1] moves between p[k] and p[k+1] (or to the
// end), as it is or reversed. With `nbrs`, k ranges over the positions next to the ends'
// neighbours (and the end of the path) only. Lookups go along the rows of the segment's ends
// (symmetric matrix) and old edges come from the edge array, as in two_opt_pass.
bool or_opt_pass(const DistanceMatrix& m, std::vector<int>& p,
                 const std::vector<std::vector<int>>* nbrs, std::vector<double>& e) {
  bool improved = false;
  const int n = static_cast<int>(p.size());
  std::vector<int> pos(m.n, -1), candidates;
  auto index_positions = [&] {
    for (int k = 0; k < n; ++k) pos[p[k]] = k;
  };
  if (nbrs) index_positions();
  edge_lengths(m, p, e);
  for (int seg = 1; seg <= 3; ++seg)
    for (int i = 1; i + seg <= n; ++i) {
      const int first = p[i], last = p[i + seg - 1];
      const int prev = p[i - 1];
      const bool at_end = i + seg == n;
      const double removal =
          at_end ? m(prev, first) : m(prev, first) + m(last, p[i + seg]) - m(prev, p[i + seg]);
      const double* row_first = &m.d[static_cast<std::size_t>(first) * m.n];
      const double* row_last = &m.d[static_cast<std::size_t>(last) * m.n];
      double best = -kEps;
      int best_k = -1;
      bool best_rev = false;
      // Both orientations of the insertion after p[k]; scan order and ties as a plain k loop.
      auto consider = [&](int k) {
        const int q = p[k];
        if (k == n - 1) {
          const double add0 = row_first[q], add1 = row_last[q];
          if (add0 - removal < best) best = add0 - removal, best_k = k, best_rev = false;
          if (add1 - removal < best) best = add1 - removal, best_k = k, best_rev = true;
          return;
        }
        const int r = p[k + 1];
        const double add0 = row_first[q] + row_last[r] - e[k];
        const double add1 = row_last[q] + row_first[r] - e[k];
        if (add0 - removal < best) best = add0 - removal, best_k = k, best_rev = false;
        if (add1 - removal < best) best = add1 - removal, best_k = k, best_rev = true;
      };
      if (nbrs) {
        candidates.clear();
        for (int end : {first, last})
          for (int q : (*nbrs)[end]) {
            candidates.push_back(pos[q]);
            if (pos[q] > 0) candidates.push_back(pos[q] - 1);
          }
        candidates.push_back(n - 1);
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
        for (const int k : candidates)
          if (k < i - 1 || k > i + seg - 1) consider(k);  // not inside or next to the segment
      } else {
        for (int k = 0; k < i - 1; ++k) consider(k);
        for (int k = i + seg; k < n; ++k) consider(k);
      }
      if (best_k < 0) continue;
      std::vector<int> segment(p.begin() + i, p.begin() + i + seg);
      if (best_rev) std::reverse(segment.begin(), segment.end());
      p.erase(p.begin() + i, p.begin() + i + seg);
      const int k = best_k < i ? best_k : best_k - seg;
      p.insert(p.begin() + k + 1, segment.begin(), segment.end());
      if (nbrs) index_positions();
      edge_lengths(m, p, e);
      improved = true;
    }
  return improved;
}

}  // namespace

bool improve_open_path(const DistanceMatrix& m, std::vector<int>& p, bool two_opt, bool or_opt,
                       const std::function<bool()>& should_stop) {
  if (p.size() < 3) return true;
  std::vector<std::vector<int>> nbrs;
  std::vector<double> edges;  // reused by every pass
  if (or_opt && m.n > kFullScanLimit) nbrs = nearest_neighbours(m);
  for (;;) {
    if (should_stop && should_stop()) return false;
    bool improved = false;
    if (two_opt) improved = two_opt_pass(m, p, edges) || improved;
    if (or_opt) improved = or_opt_pass(m, p, nbrs.empty() ? nullptr : &nbrs, edges) || improved;
    if (!improved) return true;
  }
}

}  // namespace flipper::plugins::astar
