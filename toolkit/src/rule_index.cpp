#include "flipper/toolkit/rule_index.hpp"

#include <algorithm>
#include <functional>

#include "flipper/sdk/errors.hpp"

namespace flipper::toolkit {

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

// Bucket keys spread over the table (Fibonacci hashing: the multiply mixes every key bit up).
std::size_t spread(std::uint64_t key) {
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 32);
}

std::uint64_t make_key(FirstKind kind, int first, int anchor) {
  return (static_cast<std::uint64_t>(kind) << 62) |
         (static_cast<std::uint64_t>(static_cast<std::uint32_t>(first)) << 32) |
         static_cast<std::uint32_t>(anchor + 1);
}

// An id's hash tag: its upper 32 bits; the lower bits of the tag pick the slot, so the table
// grows without hashing the ids again.
std::uint64_t id_tag(const std::string& id) {
  return static_cast<std::uint64_t>(std::hash<std::string>{}(id)) >> 32;
}

bool is_unary(const CompiledRule& c, const std::vector<Sym>& symbols) {
  return c.rhs_size == 1 && symbols[c.rhs_begin].type == Sym::Type::category;
}
}  // namespace

void RuleIndex::reset(std::shared_ptr<const sdk::Grammar> grammar) {
  grammar_ = grammar ? std::move(grammar) : std::make_shared<sdk::Grammar>();
  tokens_.clear();
  categories_.clear();
  token_uses_.clear();
  anchor_uses_.clear();
  token_first_.clear();
  category_first_.clear();
  std::fill(std::begin(class_first_), std::end(class_first_), 0);
  rules_.clear();
  symbols_.clear();
  buckets_.clear();
  bucket_count_ = 0;
  unary_.clear();
  id_slots_.clear();
  id_count_ = 0;
  root_ = intern_category(grammar_->root);
  rules_.reserve(grammar_->rules.size());
  for (const auto& r : grammar_->rules) add(r);
}

// Look up before inserting: emplace builds (allocates) a node even for a known key.
int RuleIndex::intern_token(const std::string& t) {
  if (auto it = tokens_.find(t); it != tokens_.end()) return it->second;
  const int id = static_cast<int>(tokens_.size());
  tokens_.emplace(t, id);
  token_uses_.push_back(0);
  anchor_uses_.push_back(0);
  token_first_.push_back(0);
  return id;
}

int RuleIndex::intern_category(const std::string& c) {
  if (auto it = categories_.find(c); it != categories_.end()) return it->second;
  const int id = static_cast<int>(categories_.size());
  categories_.emplace(c, id);
  unary_.emplace_back();
  category_first_.push_back(0);
  return id;
}

void RuleIndex::add(sdk::RulePtr rule) {
  if (!rule) throw sdk::Error(sdk::codes::kBadGrammar, "null rule");
  if (rule->rhs.empty())
    throw sdk::Error(sdk::codes::kBadGrammar, "rule " + rule->id + " has an empty right-hand side");
  const std::uint64_t tag = id_tag(rule->id);
  if (const int old = find_alive(rule->id, tag); old >= 0) drop(old);
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
  rules_.push_back(std::move(c));
  if (is_unary(rules_.back(), symbols_))
    unary_[static_cast<std::size_t>(symbols_[rules_.back().rhs_begin].id)].push_back(idx);
  else
    link(idx);
  index_id(idx, tag);
}

void RuleIndex::remove(const std::string& id) {
  if (const int idx = find_alive(id, id_tag(id)); idx >= 0) drop(idx);
}

void RuleIndex::drop(int idx) {
  CompiledRule& c = rules_[static_cast<std::size_t>(idx)];
  if (is_unary(c, symbols_)) {
    auto& home = unary_[static_cast<std::size_t>(symbols_[c.rhs_begin].id)];
    home.erase(std::remove(home.begin(), home.end(), idx), home.end());
  } else {
    unlink(idx);
  }
  c.alive = false;
}

// ---- buckets: (first symbol, anchor) -> a list threaded through CompiledRule::next ----------

std::uint64_t RuleIndex::bucket_key(const CompiledRule& c, const std::vector<Sym>& symbols) {
  const Sym& first = symbols[c.rhs_begin];
  switch (first.type) {
    case Sym::Type::token:
      return make_key(FirstKind::token, first.id, c.anchor);
    case Sym::Type::category:
      return make_key(FirstKind::category, first.id, c.anchor);
    default:
      return make_key(FirstKind::klass, bit_index(first.id), c.anchor);
  }
}

int& RuleIndex::first_count(const CompiledRule& c) {
  const Sym& first = symbols_[c.rhs_begin];
  const auto f = static_cast<std::size_t>(first.id);
  switch (first.type) {
    case Sym::Type::token:
      return token_first_[f];
    case Sym::Type::category:
      return category_first_[f];
    default:
      return class_first_[bit_index(first.id)];
  }
}

// The slot holding `key`, or the empty slot where it would go.
std::size_t RuleIndex::bucket_slot(std::uint64_t key) const {
  const std::size_t mask = buckets_.size() - 1;
  for (std::size_t s = spread(key) & mask;; s = (s + 1) & mask)
    if (buckets_[s].key == key || buckets_[s].key == kNoKey) return s;
}

int RuleIndex::bucket(FirstKind kind, int first, int anchor) const {
  if (buckets_.empty()) return -1;
  const std::uint64_t key = make_key(kind, first, anchor);
  const Bucket& b = buckets_[bucket_slot(key)];
  return b.key == key ? b.head : -1;
}

void RuleIndex::link(int rule) {
  if ((bucket_count_ + 1) * 2 > buckets_.size()) grow_buckets();
  CompiledRule& c = rules_[static_cast<std::size_t>(rule)];
  const std::uint64_t key = bucket_key(c, symbols_);
  Bucket& b = buckets_[bucket_slot(key)];
  if (b.key == kNoKey) {
    b.key = key;
    ++bucket_count_;
  }
  c.next = -1;
  if (c.anchor >= 0) ++anchor_uses_[static_cast<std::size_t>(c.anchor)];
  ++first_count(c);
  if (b.tail < 0)
    b.head = rule;
  else
    rules_[static_cast<std::size_t>(b.tail)].next = rule;
  b.tail = rule;
}

void RuleIndex::unlink(int rule) {
  CompiledRule& c = rules_[static_cast<std::size_t>(rule)];
  Bucket& b = buckets_[bucket_slot(bucket_key(c, symbols_))];
  int prev = -1;
  for (int r = b.head; r >= 0; prev = r, r = rules_[static_cast<std::size_t>(r)].next) {
    if (r != rule) continue;
    (prev < 0 ? b.head : rules_[static_cast<std::size_t>(prev)].next) = c.next;
    if (b.tail == rule) b.tail = prev;
    c.next = -1;
    if (c.anchor >= 0) --anchor_uses_[static_cast<std::size_t>(c.anchor)];
    --first_count(c);
    return;
  }
}

void RuleIndex::grow_buckets() {
  std::vector<Bucket> old = std::move(buckets_);
  buckets_.assign(std::max<std::size_t>(64, old.size() * 2), Bucket{});
  for (const Bucket& b : old)
    if (b.key != kNoKey) buckets_[bucket_slot(b.key)] = b;
}

// ---- rule ids ----------------------------------------------------------------------------------

int RuleIndex::find_alive(const std::string& id, std::uint64_t tag) const {
  if (id_slots_.empty()) return -1;
  const std::size_t mask = id_slots_.size() - 1;
  for (std::size_t s = tag & mask;; s = (s + 1) & mask) {
    const std::uint64_t e = id_slots_[s];
    if (e == kNoKey) return -1;
    if ((e >> 32) != tag) continue;
    const auto idx = static_cast<std::uint32_t>(e);
    const CompiledRule& c = rules_[idx];
    if (c.alive && c.rule->id == id) return static_cast<int>(idx);
  }
}

void RuleIndex::index_id(int rule, std::uint64_t tag) {
  if ((id_count_ + 1) * 2 > id_slots_.size()) grow_ids();
  const std::size_t mask = id_slots_.size() - 1;
  std::size_t s = tag & mask;
  while (id_slots_[s] != kNoKey) s = (s + 1) & mask;
  id_slots_[s] = (tag << 32) | static_cast<std::uint32_t>(rule);
  ++id_count_;
}

void RuleIndex::grow_ids() {
  std::vector<std::uint64_t> old = std::move(id_slots_);
  id_slots_.assign(std::max<std::size_t>(64, old.size() * 2), kNoKey);
  id_count_ = 0;
  const std::size_t mask = id_slots_.size() - 1;
  for (std::uint64_t e : old) {
    if (e == kNoKey || !rules_[static_cast<std::uint32_t>(e)].alive) continue;
    std::size_t s = (e >> 32) & mask;
    while (id_slots_[s] != kNoKey) s = (s + 1) & mask;
    id_slots_[s] = e;
    ++id_count_;
  }
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

}  // namespace flipper::toolkit
