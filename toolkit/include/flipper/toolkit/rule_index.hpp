#pragma once
// Compiled, interned form of a grammar for the toolkit's chart parsers (chart_run.hpp; the
// plugins `chart` and `floating`): tokens and categories become ints, right-hand sides live in one
// pool, and rules are indexed by their first RHS symbol (token, token class or category) and their
// *anchor*, the rarest token among the rest of their RHS, so a parse only looks at rules whose
// first symbol and anchor both occur in the utterance (docs/naturalization.md §2, "Rule
// selection"). Unary rules are indexed by their single category. Building is linear in the rules
// and allocates nothing per rule: the RHS symbols share one pool, the buckets are lists threaded
// through the rules, and the bucket and id tables are open-addressing arrays (100k rules: ~18 ms,
// 1.2k instructions per rule; with node-based maps and a vector per rule it took 2.5x that).
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "flipper/sdk/grammar.hpp"

namespace flipper::toolkit {

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
  std::uint32_t rhs_begin = 0;  ///< first symbol in RuleIndex's symbol pool
  std::uint32_t rhs_size = 0;
  int anchor = -1;  ///< token id of the rarest token of rhs[1..] when added; -1: none
  int next = -1;    ///< the next rule of the same bucket (ascending), -1: last
  bool alive = true;
};

/// How the rules that may start at a position are grouped: by the kind of their first symbol.
enum class FirstKind : std::uint8_t { token, klass, category };

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
  /// token_id / classes_of of each token of an utterance.
  std::vector<int> token_ids(const std::vector<std::string>& tokens) const;
  std::vector<std::uint8_t> classes(const std::vector<std::string>& tokens) const;

  const std::vector<CompiledRule>& rules() const { return rules_; }
  std::span<const Sym> rhs(const CompiledRule& rule) const {
    return {symbols_.data() + rule.rhs_begin, rule.rhs_size};
  }
  std::span<const Sym> rhs(int rule) const { return rhs(rules_[static_cast<std::size_t>(rule)]); }
  /// The first of the alive non-unary rules whose first symbol is `first` (a token id, a class bit
  /// index 0-3 or a category id, by `kind`) and whose anchor is `anchor` (-1: rules without one);
  /// the others follow through CompiledRule::next, ascending. -1: none.
  int bucket(FirstKind kind, int first, int anchor) const;
  /// How many alive non-unary rules have the first symbol `first` (kind as in bucket).
  int starting(FirstKind kind, int first) const {
    const auto f = static_cast<std::size_t>(first);
    return kind == FirstKind::token      ? token_first_[f]
           : kind == FirstKind::category ? category_first_[f]
                                         : class_first_[f];
  }
  /// How many alive rules have `token` as their anchor.
  int anchors(int token) const { return anchor_uses_[static_cast<std::size_t>(token)]; }
  const std::vector<int>& unary_from(int cat) const {
    return unary_[static_cast<std::size_t>(cat)];
  }

 private:
  int intern_token(const std::string& t);
  int intern_category(const std::string& c);
  struct Bucket {
    std::uint64_t key = kNoKey;
    int head = -1, tail = -1;
  };
  static constexpr std::uint64_t kNoKey = ~std::uint64_t{0};
  static std::uint64_t bucket_key(const CompiledRule& c, const std::vector<Sym>& symbols);
  std::size_t bucket_slot(std::uint64_t key) const;
  int& first_count(const CompiledRule& c);
  void link(int rule);
  void unlink(int rule);
  void grow_buckets();
  int find_alive(const std::string& id, std::uint64_t tag) const;  ///< tag: id_tag(id)
  void index_id(int rule, std::uint64_t tag);
  void drop(int rule);
  void grow_ids();

  std::shared_ptr<const sdk::Grammar> grammar_ = std::make_shared<sdk::Grammar>();
  std::unordered_map<std::string, int> tokens_;
  std::unordered_map<std::string, int> categories_;
  std::vector<int> token_uses_;   ///< per token: rules that have it in rhs[1..] (anchor choice)
  std::vector<int> anchor_uses_;  ///< per token: alive rules anchored on it
  std::vector<int> token_first_, category_first_;  ///< per token / category: see starting()
  int class_first_[4] = {0, 0, 0, 0};
  std::vector<CompiledRule> rules_;
  std::vector<Sym> symbols_;
  std::vector<Bucket> buckets_;  ///< open addressing by key, power-of-two size
  std::size_t bucket_count_ = 0;
  std::vector<std::vector<int>> unary_;
  /// Rule ids: (upper 32 bits of the id's hash, rule number) per slot, linear probing; entries of
  /// removed rules stay until the table grows (rules_ keeps those rules too) and are skipped.
  std::vector<std::uint64_t> id_slots_;
  std::size_t id_count_ = 0;
  int root_ = -1;
};

}  // namespace flipper::toolkit
