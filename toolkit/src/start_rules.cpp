#include "flipper/toolkit/start_rules.hpp"

#include <algorithm>

namespace flipper::toolkit {

StartRules::StartRules(const RuleIndex& index, const std::vector<int>& token_ids,
                       const std::vector<std::uint8_t>& classes, const Visible& visible,
                       bool exhaustive)
    : index_(index),
      visible_fn_(visible),
      exhaustive_(exhaustive),
      n_(static_cast<int>(token_ids.size())) {
  classes_from_.assign(static_cast<std::size_t>(n_) + 1, 0);
  for (int p = n_ - 1; p >= 0; --p)
    classes_from_[static_cast<std::size_t>(p)] =
        classes_from_[static_cast<std::size_t>(p) + 1] | classes[static_cast<std::size_t>(p)];
  for (int p = 0; p < n_; ++p)
    if (token_ids[static_cast<std::size_t>(p)] >= 0)
      last_at_.emplace_back(token_ids[static_cast<std::size_t>(p)], p);
  // Sorted by token, then position: the last entry of each token is its last position.
  std::sort(last_at_.begin(), last_at_.end());
  std::vector<std::pair<int, int>> last;
  for (std::size_t k = 0; k < last_at_.size(); ++k)
    if (k + 1 == last_at_.size() || last_at_[k + 1].first != last_at_[k].first)
      last.push_back(last_at_[k]);
  last_at_ = std::move(last);
  for (const auto& tl : last_at_)
    if (index.anchors(tl.first) > 0) anchors_.push_back(tl);
  lists_.resize(static_cast<std::size_t>(n_));
}

int StartRules::last_position(int token) const {
  auto it = std::lower_bound(last_at_.begin(), last_at_.end(), std::make_pair(token, -1));
  return it != last_at_.end() && it->first == token ? it->second : -1;
}

bool StartRules::visible(int rule) {
  if (!visible_fn_) return true;
  auto [it, fresh] = visible_.try_emplace(rule, false);
  if (fresh) it->second = visible_fn_(*index_.rules()[static_cast<std::size_t>(rule)].rule);
  return it->second;
}

bool StartRules::fits_after(const CompiledRule& rule, int i) const {
  if (static_cast<int>(rule.rhs_size) > n_ - i) return false;
  const auto rhs = index_.rhs(rule);
  for (std::size_t k = 1; k < rhs.size(); ++k) {
    const int pos = i + static_cast<int>(k);
    const Sym& s = rhs[k];
    if (s.type == Sym::Type::token && last_position(s.id) < pos) return false;
    if (s.type == Sym::Type::klass && !(classes_from_[static_cast<std::size_t>(pos)] & s.id))
      return false;
  }
  return true;
}

std::span<const int> StartRules::at(int i, FirstKind kind, int first) {
  const std::uint32_t key =
      (static_cast<std::uint32_t>(kind) << 30) | static_cast<std::uint32_t>(first);
  if (exhaustive_) {
    if (all_.empty()) scan_all();
    return all_[key];  // the same list at every position
  }
  if (index_.starting(kind, first) == 0) return {};
  auto& here = lists_[static_cast<std::size_t>(i)];
  for (const List& l : here)
    if (l.key == key) return {pool_.data() + l.begin, l.size};
  const auto begin = static_cast<std::uint32_t>(pool_.size());
  const auto& rules = index_.rules();
  // Each bucket is ascending: merge it in (most positions see one or two buckets).
  auto take = [&](int head) {
    const auto mid = static_cast<std::ptrdiff_t>(pool_.size());
    for (int r = head; r >= 0; r = rules[static_cast<std::size_t>(r)].next)
      if (fits_after(rules[static_cast<std::size_t>(r)], i) && visible(r)) pool_.push_back(r);
    std::inplace_merge(pool_.begin() + begin, pool_.begin() + mid, pool_.end());
  };
  take(index_.bucket(kind, first, -1));
  for (const auto& [token, last] : anchors_)
    if (last > i) take(index_.bucket(kind, first, token));
  here.push_back({key, begin, static_cast<std::uint32_t>(pool_.size()) - begin});
  return {pool_.data() + begin, here.back().size};
}

// The unindexed matcher's candidates, once per parse: every alive, visible, non-unary rule, listed
// under its first symbol.
void StartRules::scan_all() {
  const auto& rules = index_.rules();
  for (std::size_t r = 0; r < rules.size(); ++r) {
    const CompiledRule& c = rules[r];
    const Sym& s = index_.rhs(c)[0];
    if (!c.alive || (s.type == Sym::Type::category && c.rhs_size == 1)) continue;
    if (!visible(static_cast<int>(r))) continue;
    const FirstKind kind = s.type == Sym::Type::token      ? FirstKind::token
                           : s.type == Sym::Type::category ? FirstKind::category
                                                           : FirstKind::klass;
    const int first = kind != FirstKind::klass ? s.id
                      : s.id == kNumber        ? 0
                      : s.id == kColor         ? 1
                      : s.id == kShape         ? 2
                                               : 3;
    all_[(static_cast<std::uint32_t>(kind) << 30) | static_cast<std::uint32_t>(first)].push_back(
        static_cast<int>(r));
  }
  all_[~std::uint32_t{0}];  // marks the scan done, even when no rule was found
}

}  // namespace flipper::toolkit
