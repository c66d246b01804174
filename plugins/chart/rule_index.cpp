#include "rule_index.hpp"

#include <algorithm>
#include <functional>

#include "flipper/sdk/errors.hpp"

namespace flipper::chart {

namespace {
int bit_index(sdk::Symbol::Type t) {
  switch (t) {
    case sdk::Symbol::Type::number:
      return 0;
    case sdk::Symbol::Type::color:
      return 1;
    case sdk::Symbol::Type::shape:
      return 2;
    case sdk::Symbol::Type::direction:
      return 3;
    default:
      return -1;
  }
}

int bit_index(int bit) {
  return bit == kNumber ? 0 : bit == kColor ? 1 : bit == kShape ? 2 : 3;
}

const std::vector<int> kNone;
}  // namespace

void RuleIndex::reset(std::shared_ptr<const sdk::Grammar> grammar) {
  grammar_ = grammar ? std::move(grammar) : std::make_shared<sdk::Grammar>();
  tokens_.clear();
  categories_.clear();
  token_uses_.clear();
  rules_.clear();
  symbols_.clear();
  buckets_.clear();
  unary_.clear();
  id_slots_.clear();
  id_count_ = 0;
  root_ = intern_category(grammar_->root);
  rules_.reserve(grammar_->rules.size());
  for (const auto& r : grammar_->rules) add(r);
}

int RuleIndex::intern_token(const std::string& t) {
  auto [it, fresh] = tokens_.emplace(t, static_cast<int>(tokens_.size()));
  if (fresh) token_uses_.push_back(0);
  return it->second;
}

int RuleIndex::intern_category(const std::string& c) {
  auto [it, fresh] = categories_.emplace(c, static_cast<int>(categories_.size()));
  if (fresh) unary_.emplace_back();
  return it->second;
}

std::uint64_t RuleIndex::bucket_key(FirstKind kind, int first, int anchor) {
  return (static_cast<std::uint64_t>(kind) << 62) |
         (static_cast<std::uint64_t>(static_cast<std::uint32_t>(first)) << 32) |
         static_cast<std::uint32_t>(anchor + 1);
}

const std::vector<int>& RuleIndex::bucket(FirstKind kind, int first, int anchor) const {
  auto it = buckets_.find(bucket_key(kind, first, anchor));
  return it == buckets_.end() ? kNone : it->second;
}

// The list a compiled rule belongs to (unary rules: by their category; others: their bucket).
std::vector<int>* RuleIndex::home_of(const CompiledRule& c) {
  const Sym& first = symbols_[c.rhs_begin];
  if (c.rhs_size == 1 && first.type == Sym::Type::category)
    return &unary_[static_cast<std::size_t>(first.id)];
  const FirstKind kind = first.type == Sym::Type::token      ? FirstKind::token
                         : first.type == Sym::Type::category ? FirstKind::category
                                                             : FirstKind::klass;
  const int key = kind == FirstKind::klass ? bit_index(first.id) : first.id;
  return &buckets_[bucket_key(kind, key, c.anchor)];
}

void RuleIndex::add(sdk::RulePtr rule) {
  if (!rule) throw sdk::Error(sdk::codes::kBadGrammar, "null rule");
  if (rule->rhs.empty())
    throw sdk::Error(sdk::codes::kBadGrammar, "rule " + rule->id + " has an empty right-hand side");
  if (find_alive(rule->id) >= 0) remove(rule->id);
  CompiledRule c;
  c.lhs = intern_category(rule->lhs);
  c.rhs_begin = static_cast<std::uint32_t>(symbols_.size());
  c.rhs_size = static_cast<std::uint32_t>(rule->rhs.size());
  for (std::size_t k = 0; k < rule->rhs.size(); ++k) {
    const sdk::Symbol& s = rule->rhs[k];
    Sym sym;
    switch (s.type) {
      case sdk::Symbol::Type::token:
        sym.type = Sym::Type::token;
        sym.id = intern_token(s.text);
        // The anchor: the token fewest rules had so far (a rarer token selects fewer rules).
        if (k > 0 && (c.anchor < 0 || token_uses_[static_cast<std::size_t>(sym.id)] <
                                          token_uses_[static_cast<std::size_t>(c.anchor)]))
          c.anchor = sym.id;
        break;
      case sdk::Symbol::Type::category:
        sym.type = Sym::Type::category;
        sym.id = intern_category(s.text);
        break;
      default:
        sym.type = Sym::Type::klass;
        sym.id = 1 << bit_index(s.type);
        break;
    }
    symbols_.push_back(sym);
  }
  for (std::size_t k = c.rhs_begin + 1; k < symbols_.size(); ++k)
    if (symbols_[k].type == Sym::Type::token)
      ++token_uses_[static_cast<std::size_t>(symbols_[k].id)];
  c.rule = std::move(rule);
  const int idx = static_cast<int>(rules_.size());
  home_of(c)->push_back(idx);
  rules_.push_back(std::move(c));
  index_id(idx);
}

void RuleIndex::remove(const std::string& id) {
  const int idx = find_alive(id);
  if (idx < 0) return;
  CompiledRule& c = rules_[static_cast<std::size_t>(idx)];
  std::vector<int>& home = *home_of(c);
  home.erase(std::remove(home.begin(), home.end(), idx), home.end());
  c.alive = false;
}

// ---- rule ids: linear probing over rule numbers, hashed by the rule's id ----------------------

int RuleIndex::find_alive(const std::string& id) const {
  if (id_slots_.empty()) return -1;
  const std::size_t mask = id_slots_.size() - 1;
  for (std::size_t s = std::hash<std::string>{}(id)&mask;; s = (s + 1) & mask) {
    const int idx = id_slots_[s];
    if (idx < 0) return -1;
    const CompiledRule& c = rules_[static_cast<std::size_t>(idx)];
    if (c.alive && c.rule->id == id) return idx;
  }
}

void RuleIndex::index_id(int rule) {
  if ((id_count_ + 1) * 2 > id_slots_.size()) grow_ids();
  const std::size_t mask = id_slots_.size() - 1;
  std::size_t s = std::hash<std::string>{}(rules_[static_cast<std::size_t>(rule)].rule->id) & mask;
  while (id_slots_[s] >= 0) s = (s + 1) & mask;
  id_slots_[s] = rule;
  ++id_count_;
}

void RuleIndex::grow_ids() {
  std::vector<int> old = std::move(id_slots_);
  id_slots_.assign(std::max<std::size_t>(64, old.size() * 2), -1);
  id_count_ = 0;
  for (int idx : old)
    if (idx >= 0 && rules_[static_cast<std::size_t>(idx)].alive) index_id(idx);
}

// ---- lookups ---------------------------------------------------------------------------------

int RuleIndex::token_id(const std::string& token) const {
  auto it = tokens_.find(token);
  return it == tokens_.end() ? -1 : it->second;
}

int RuleIndex::category_id(const std::string& category) const {
  auto it = categories_.find(category);
  return it == categories_.end() ? -1 : it->second;
}

std::uint8_t RuleIndex::classes_of(const std::string& token) const {
  std::uint8_t bits = 0;
  if (sdk::class_matches(*grammar_, sdk::Symbol::Type::number, token)) bits |= kNumber;
  if (sdk::class_matches(*grammar_, sdk::Symbol::Type::color, token)) bits |= kColor;
  if (sdk::class_matches(*grammar_, sdk::Symbol::Type::shape, token)) bits |= kShape;
  if (sdk::class_matches(*grammar_, sdk::Symbol::Type::direction, token)) bits |= kDirection;
  return bits;
}

std::vector<int> RuleIndex::token_ids(const std::vector<std::string>& tokens) const {
  std::vector<int> ids;
  ids.reserve(tokens.size());
  for (const auto& t : tokens) ids.push_back(token_id(t));
  return ids;
}

std::vector<std::uint8_t> RuleIndex::classes(const std::vector<std::string>& tokens) const {
  std::vector<std::uint8_t> bits;
  bits.reserve(tokens.size());
  for (const auto& t : tokens) bits.push_back(classes_of(t));
  return bits;
}

}  // namespace flipper::chart
