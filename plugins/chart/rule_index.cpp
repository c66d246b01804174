#include "rule_index.hpp"

#include <algorithm>

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
}  // namespace

void RuleIndex::reset(std::shared_ptr<const sdk::Grammar> grammar) {
  grammar_ = grammar ? std::move(grammar) : std::make_shared<sdk::Grammar>();
  tokens_.clear();
  categories_.clear();
  by_id_.clear();
  rules_.clear();
  by_token_.clear();
  for (auto& v : by_class_) v.clear();
  by_category_.clear();
  unary_.clear();
  root_ = intern_category(grammar_->root);
  for (const auto& r : grammar_->rules) add(r);
}

int RuleIndex::intern_token(const std::string& t) {
  auto [it, fresh] = tokens_.emplace(t, static_cast<int>(tokens_.size()));
  if (fresh) by_token_.emplace_back();
  return it->second;
}

int RuleIndex::intern_category(const std::string& c) {
  auto [it, fresh] = categories_.emplace(c, static_cast<int>(categories_.size()));
  if (fresh) {
    by_category_.emplace_back();
    unary_.emplace_back();
  }
  return it->second;
}

void RuleIndex::add(sdk::RulePtr rule) {
  if (!rule) throw sdk::Error(sdk::codes::kBadGrammar, "null rule");
  if (rule->rhs.empty())
    throw sdk::Error(sdk::codes::kBadGrammar, "rule " + rule->id + " has an empty right-hand side");
  if (by_id_.count(rule->id)) remove(rule->id);
  CompiledRule c;
  c.lhs = intern_category(rule->lhs);
  for (const auto& s : rule->rhs) {
    Sym sym;
    switch (s.type) {
      case sdk::Symbol::Type::token:
        sym.type = Sym::Type::token;
        sym.id = intern_token(s.text);
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
    c.rhs.push_back(sym);
  }
  c.rule = std::move(rule);
  const int idx = static_cast<int>(rules_.size());
  const Sym& first = c.rhs.front();
  if (c.rhs.size() == 1 && first.type == Sym::Type::category) {
    unary_[first.id].push_back(idx);
  } else if (first.type == Sym::Type::token) {
    by_token_[first.id].push_back(idx);
  } else if (first.type == Sym::Type::category) {
    by_category_[first.id].push_back(idx);
  } else {
    by_class_[bit_index(c.rule->rhs.front().type)].push_back(idx);
  }
  by_id_[c.rule->id] = idx;
  rules_.push_back(std::move(c));
}

void RuleIndex::unindex(int idx) {
  auto drop = [idx](std::vector<int>& v) {
    v.erase(std::remove(v.begin(), v.end(), idx), v.end());
  };
  const CompiledRule& c = rules_[idx];
  const Sym& first = c.rhs.front();
  if (c.rhs.size() == 1 && first.type == Sym::Type::category)
    drop(unary_[first.id]);
  else if (first.type == Sym::Type::token)
    drop(by_token_[first.id]);
  else if (first.type == Sym::Type::category)
    drop(by_category_[first.id]);
  else
    drop(by_class_[bit_index(c.rule->rhs.front().type)]);
}

void RuleIndex::remove(const std::string& id) {
  auto it = by_id_.find(id);
  if (it == by_id_.end()) return;
  unindex(it->second);
  rules_[it->second].alive = false;
  by_id_.erase(it);
}

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

}  // namespace flipper::chart
