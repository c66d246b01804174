#include "word_similarity.hpp"

#include <algorithm>
#include <deque>

namespace flipper::plugins::wordnet {

namespace {
// Caches are dropped wholesale past these sizes, which keeps memory bounded on long sessions.
constexpr std::size_t kMaxPairs = 200000;
constexpr std::size_t kMaxSynsetEntries = 200000;
}  // namespace

const WordSimilarity::Closure& WordSimilarity::closure(std::uint32_t offset, Pos pos) const {
  auto it = closures_.find(key(offset, pos));
  if (it != closures_.end()) return it->second;
  // Breadth-first up the hypernym links: the first visit of an ancestor is its distance.
  std::unordered_map<std::uint32_t, int> dist{{offset, 0}};
  std::deque<std::uint32_t> queue{offset};
  while (!queue.empty()) {
    const std::uint32_t s = queue.front();
    queue.pop_front();
    for (std::uint32_t h : db_.hypernyms(s, pos))
      if (dist.emplace(h, dist[s] + 1).second) queue.push_back(h);
  }
  Closure c(dist.begin(), dist.end());
  std::sort(c.begin(), c.end());
  if (closures_.size() > kMaxSynsetEntries) closures_.clear();
  return closures_.emplace(key(offset, pos), std::move(c)).first->second;
}

int WordSimilarity::depth(std::uint32_t offset, Pos pos) const {
  auto it = depths_.find(key(offset, pos));
  if (it != depths_.end()) return it->second;
  int best = 0;
  for (const auto& [ancestor, d] : closure(offset, pos))
    if (db_.hypernyms(ancestor, pos).empty() && (best == 0 || d + 1 < best)) best = d + 1;
  if (depths_.size() > kMaxSynsetEntries) depths_.clear();
  depths_[key(offset, pos)] = best;
  return best;
}

const std::vector<std::uint32_t>& WordSimilarity::synsets(const std::string& word, Pos pos) const {
  auto& cache = synsets_[static_cast<std::size_t>(pos)];
  auto it = cache.find(word);
  if (it != cache.end()) return it->second;
  if (cache.size() > kMaxSynsetEntries) cache.clear();
  return cache.emplace(word, db_.synsets(word, pos)).first->second;
}

double WordSimilarity::synset_score(std::uint32_t a, std::uint32_t b, Pos pos) const {
  if (a == b) return 1.0;
  // Copies: computing depths below may insert into (and rehash) the closure cache.
  const Closure ca = closure(a, pos);
  const Closure cb = closure(b, pos);
  double best = 0;
  auto i = ca.begin();
  auto j = cb.begin();
  while (i != ca.end() && j != cb.end()) {
    if (i->first < j->first) {
      ++i;
    } else if (j->first < i->first) {
      ++j;
    } else {
      const double d = depth(i->first, pos);
      best = std::max(best, 2 * d / (i->second + j->second + 2 * d));
      ++i;
      ++j;
    }
  }
  return best;
}

double WordSimilarity::compute(const std::string& a, const std::string& b) const {
  double best = 0;
  for (Pos pos : {Pos::noun, Pos::verb, Pos::adj, Pos::adv}) {
    const auto sa = synsets(a, pos);  // copy: the cache may rehash while we look up b
    const auto& sb = synsets(b, pos);
    for (std::uint32_t x : sa)
      for (std::uint32_t y : sb) {
        if (x == y) return 1.0;
        if (pos == Pos::noun || pos == Pos::verb) best = std::max(best, synset_score(x, y, pos));
      }
  }
  return best;
}

double WordSimilarity::operator()(std::string_view a, std::string_view b) const {
  if (a == b) return 1.0;
  if (a.empty() || b.empty()) return 0.0;
  // Symmetric by construction: the pair is cached and computed in one canonical order.
  std::string x(a < b ? a : b), y(a < b ? b : a);
  std::string pair_key = x + '\n' + y;
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = pairs_.find(pair_key);
  if (it != pairs_.end()) return it->second;
  const double s = compute(x, y);
  if (pairs_.size() > kMaxPairs) pairs_.clear();
  pairs_.emplace(std::move(pair_key), s);
  return s;
}

}  // namespace flipper::plugins::wordnet
