#pragma once
// Compiled, interned form of a grammar for the chart parser: tokens and categories become ints,
// rules are indexed by their first RHS symbol (token, token class or category) and unary rules
// by their single category, so a parse never builds strings or scans unrelated rules.
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "flipper/sdk/grammar.hpp"

namespace flipper::chart {

/// A token class bit (@number, @color, @shape, @direction).
enum ClassBit : std::uint8_t { kNumber = 1, kColor = 2, kShape = 4, kDirection = 8 };

struct Sym {
  enum class Type : std::uint8_t { token, category, klass };
  Type type = Type::token;
  int id = -1;  ///< token id, category id, or ClassBit
};

struct CompiledRule {
  sdk::RulePtr rule;
  int lhs = -1;
  std::vector<Sym> rhs;
  bool alive = true;
};

class RuleIndex {
 public:
  void reset(std::shared_ptr<const sdk::Grammar> grammar);
  void add(sdk::RulePtr rule);
  void remove(const std::string& id);

  const sdk::Grammar& grammar() const { return *grammar_; }
  int token_id(const std::string& token) const;        ///< -1 if no rule mentions it
  int category_id(const std::string& category) const;  ///< -1 if unknown
  int root() const { return root_; }
  std::size_t category_count() const { return categories_.size(); }
  /// Class bits matched by a token (computed once per parse token).
  std::uint8_t classes_of(const std::string& token) const;

  const std::vector<CompiledRule>& rules() const { return rules_; }
  const std::vector<int>& by_first_token(int token) const { return by_token_[token]; }
  const std::vector<int>& by_first_class(int bit_index) const { return by_class_[bit_index]; }
  const std::vector<int>& by_first_category(int cat) const { return by_category_[cat]; }
  const std::vector<int>& unary_from(int cat) const { return unary_[cat]; }

 private:
  int intern_token(const std::string& t);
  int intern_category(const std::string& c);
  void unindex(int rule_index);

  std::shared_ptr<const sdk::Grammar> grammar_ = std::make_shared<sdk::Grammar>();
  std::unordered_map<std::string, int> tokens_;
  std::unordered_map<std::string, int> categories_;
  std::unordered_map<std::string, int> by_id_;
  std::vector<CompiledRule> rules_;
  std::vector<std::vector<int>> by_token_;
  std::vector<int> by_class_[4];
  std::vector<std::vector<int>> by_category_;
  std::vector<std::vector<int>> unary_;
  int root_ = -1;
};

}  // namespace flipper::chart
