// Plugin answers as bytes and back (flipper/sdk/answer_wire.hpp, docs/plugins-untrusted.md §6).
// A parse result is three tables, each entry after the ones it points to: program nodes, rules,
// derivations; then the candidates and the chart by index. A reference is 0 (null) or 1 + the
// entry's index (Table below).
#include "flipper/sdk/answer_wire.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>

#include "node_storage.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {
namespace host {
namespace {

class Bytes {
 public:
  template <class T>
  void put(const T& v) {
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put_text(const std::string& s) {
    put<std::uint64_t>(s.size());
    out_ += s;
  }
  void append(const Bytes& more) { out_ += more.out_; }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

struct Malformed {};

// Reads what Bytes wrote; throws Malformed at the first length, index or value that does not fit.
class Reader {
 public:
  explicit Reader(std::string_view in) : in_(in) {}
  template <class T>
  T get() {
    T v{};
    need(sizeof v);
    std::memcpy(&v, in_.data(), sizeof v);
    in_.remove_prefix(sizeof v);
    return v;
  }
  // A count of elements of at least `each` bytes each that the rest can hold.
  std::uint64_t count(std::size_t each) {
    const auto n = get<std::uint64_t>();
    need(n > in_.size() / each ? in_.size() + 1 : n * each);
    return n;
  }
  // A value below `end` (an enumeration's size, a table's length).
  template <class T>
  T below(std::uint64_t end) {
    const auto v = get<T>();
    if (static_cast<std::uint64_t>(v) >= end) throw Malformed{};
    return v;
  }
  bool flag() { return below<std::uint8_t>(2) != 0; }
  std::string text() {
    const auto n = count(1);
    std::string s(in_.substr(0, n));
    in_.remove_prefix(n);
    return s;
  }
  void done() const {
    if (!in_.empty()) throw Malformed{};
  }

 private:
  std::string_view in_;
  void need(std::size_t n) const {
    if (n > in_.size()) throw Malformed{};
  }
};

template <class Result, class Decode>
std::optional<Result> decoded(std::string_view bytes, Decode decode) {
  try {
    return decode(bytes);
  } catch (const Malformed&) {
    return std::nullopt;
  }
}

std::string path_bytes(const PathResult& r) {
  Bytes b;
  b.put(r.status);
  b.put(r.target);
  b.put<std::uint64_t>(r.path.size());
  for (const Cell& c : r.path) b.put(c);
  b.put(r.expansions);
  b.put_text(r.message);
  return b.take();
}

PathResult path_of(std::string_view bytes) {
  Reader in(bytes);
  PathResult r;
  r.status = in.below<PlanStatus>(4);
  r.target = in.get<Cell>();
  r.path.resize(in.count(sizeof(Cell)));
  for (Cell& c : r.path) c = in.get<Cell>();
  r.expansions = in.get<std::uint64_t>();
  r.message = in.text();
  in.done();
  return r;
}

std::string tour_bytes(const TourResult& t) {
  Bytes b;
  b.put(t.status);
  b.put<std::uint64_t>(t.order.size());
  for (const std::size_t i : t.order) b.put<std::uint64_t>(i);
  b.put(t.length);
  return b.take();
}

TourResult tour_of(std::string_view bytes) {
  Reader in(bytes);
  TourResult t;
  t.status = in.below<PlanStatus>(4);
  t.order.resize(in.count(sizeof(std::uint64_t)));
  for (std::size_t& i : t.order) i = static_cast<std::size_t>(in.get<std::uint64_t>());
  t.length = in.get<double>();
  in.done();
  return t;
}

// Writes each distinct object once, kids first; a reference is 0 (null) or 1 + the index.
class Writer {
 public:
  std::uint64_t node(const Program& p) {
    if (!p) return 0;
    if (auto it = nodes_.find(p.get()); it != nodes_.end()) return it->second;
    std::vector<std::uint64_t> kids;
    kids.reserve(p->kids.size());
    for (const Program& k : p->kids) kids.push_back(node(k));
    node_table_.put(static_cast<std::uint8_t>(p->kind));
    node_table_.put(static_cast<std::uint8_t>(p->sort));
    node_table_.put(p->number);
    node_table_.put_text(p->text);
    node_table_.put(static_cast<std::int32_t>(p->index));
    node_table_.put(static_cast<std::uint64_t>(p->hash));
    node_table_.put(p->size);
    put_refs(node_table_, kids);
    return nodes_[p.get()] = nodes_.size() + 1;
  }
  std::uint64_t rule(const RulePtr& r) {
    if (!r) return 0;
    if (auto it = rules_.find(r.get()); it != rules_.end()) return it->second;
    const std::uint64_t sem = node(r->sem);
    rule_table_.put_text(r->id);
    rule_table_.put_text(r->lhs);
    rule_table_.put<std::uint64_t>(r->rhs.size());
    for (const Symbol& s : r->rhs) {
      rule_table_.put(static_cast<std::uint8_t>(s.type));
      rule_table_.put_text(s.text);
    }
    rule_table_.put(sem);
    rule_table_.put(static_cast<std::uint8_t>(r->induced));
    rule_table_.put(static_cast<std::uint8_t>(r->how));
    rule_table_.put_text(r->author);
    rule_table_.put_text(r->head);
    rule_table_.put<std::uint64_t>(r->body.size());
    for (const std::string& line : r->body) rule_table_.put_text(line);
    rule_table_.put(r->created);
    return rules_[r.get()] = rules_.size() + 1;
  }
  std::uint64_t derivation(const DerivationPtr& d) {
    if (!d) return 0;
    if (auto it = derivations_.find(d.get()); it != derivations_.end()) return it->second;
    std::vector<std::uint64_t> kids;
    kids.reserve(d->kids.size());
    for (const DerivationPtr& k : d->kids) kids.push_back(derivation(k));
    const std::uint64_t rule_ref = rule(d->rule), sem = node(d->sem);
    derivation_table_.put(rule_ref);
    derivation_table_.put(static_cast<std::int32_t>(d->start));
    derivation_table_.put(static_cast<std::int32_t>(d->end));
    put_refs(derivation_table_, kids);
    derivation_table_.put(sem);
    derivation_table_.put(d->score);
    derivation_table_.put(static_cast<std::uint8_t>(d->core_only));
    derivation_table_.put(d->newest_rule);
    return derivations_[d.get()] = derivations_.size() + 1;
  }
  // The tables, then `tail` (which refers to them).
  std::string take(const Bytes& tail) {
    Bytes all;
    all.put<std::uint64_t>(nodes_.size());
    all.append(node_table_);
    all.put<std::uint64_t>(rules_.size());
    all.append(rule_table_);
    all.put<std::uint64_t>(derivations_.size());
    all.append(derivation_table_);
    all.append(tail);
    return all.take();
  }
  static void put_refs(Bytes& b, const std::vector<std::uint64_t>& refs) {
    b.put<std::uint64_t>(refs.size());
    for (const std::uint64_t r : refs) b.put(r);
  }

 private:
  std::unordered_map<const void*, std::uint64_t> nodes_, rules_, derivations_;
  Bytes node_table_, rule_table_, derivation_table_;
};

// How deep a program or derivation may nest: the parent's recursive checks and destructors get
// a bounded stack (a parse of input.max_tokens tokens nests far less).
constexpr std::uint32_t kMaxDepth = 10000;

// A table being read: a reference is to an entry read before (one not read yet reads as null,
// which the answer check refuses), so what is built has no cycle, and nests at most kMaxDepth.
template <class Ptr>
struct Table {
  std::vector<Ptr> items;
  std::vector<std::uint32_t> depth;
  explicit Table(std::uint64_t n) : items(n), depth(n, 0) {}
  Ptr ref(Reader& in, std::uint32_t& deepest) const {
    const auto r = in.below<std::uint64_t>(items.size() + 1);
    if (r == 0) return nullptr;
    deepest = std::max(deepest, depth[r - 1]);
    return items[r - 1];
  }
  Ptr ref(Reader& in) const {
    std::uint32_t unused = 0;
    return ref(in, unused);
  }
  std::vector<Ptr> refs(Reader& in, std::uint32_t& deepest) const {
    std::vector<Ptr> out(in.count(sizeof(std::uint64_t)));
    for (Ptr& p : out) p = ref(in, deepest);
    return out;
  }
  std::vector<Ptr> refs(Reader& in) const {
    std::uint32_t unused = 0;
    return refs(in, unused);
  }
  void set(std::size_t i, Ptr p, std::uint32_t deepest_kid) {
    if (deepest_kid >= kMaxDepth) throw Malformed{};
    items[i] = std::move(p);
    depth[i] = deepest_kid + 1;
  }
};

constexpr std::uint64_t kKindCount = static_cast<std::uint64_t>(Kind::Hole) + 1;
constexpr std::uint64_t kSorts = static_cast<std::uint64_t>(Sort::Property) + 1;
constexpr std::uint64_t kSymbols = static_cast<std::uint64_t>(Symbol::Type::direction) + 1;
constexpr std::uint64_t kOrigins = static_cast<std::uint64_t>(RuleOrigin::rewriting) + 1;

}  // namespace

std::string to_bytes(const PathResult& r) {
  return path_bytes(r);
}
std::string to_bytes(const TourResult& t) {
  return tour_bytes(t);
}

std::string to_bytes(const ParseResult& result) {
  Writer w;
  Bytes tail;
  std::vector<std::uint64_t> chart;
  for (const DerivationPtr& d : result.chart) chart.push_back(w.derivation(d));
  tail.put<std::uint64_t>(result.candidates.size());
  for (const Candidate& c : result.candidates) {
    std::vector<std::uint64_t> derivations;
    for (const DerivationPtr& d : c.derivations) derivations.push_back(w.derivation(d));
    tail.put(w.node(c.program));
    Writer::put_refs(tail, derivations);
    tail.put(c.score);
    tail.put(static_cast<std::uint8_t>(c.core_only));
    tail.put(c.newest_rule);
  }
  Writer::put_refs(tail, chart);
  tail.put(static_cast<std::uint8_t>(result.stopped));
  tail.put(result.derivations);
  return w.take(tail);
}

namespace {
ParseResult parse_of(std::string_view bytes) {
  Reader in(bytes);
  Table<Program> nodes(in.count(1));
  for (std::size_t i = 0; i < nodes.items.size(); ++i) {
    auto n = detail::new_node();
    n->kind = static_cast<Kind>(in.below<std::uint8_t>(kKindCount));
    n->sort = static_cast<Sort>(in.below<std::uint8_t>(kSorts));
    n->number = in.get<double>();
    n->text = in.text();
    n->index = in.get<std::int32_t>();
    n->hash = static_cast<std::size_t>(in.get<std::uint64_t>());
    n->size = in.get<std::uint32_t>();
    std::uint32_t deepest = 0;
    n->kids = nodes.refs(in, deepest);
    nodes.set(i, std::move(n), deepest);
  }
  Table<RulePtr> rules(in.count(1));
  for (std::size_t i = 0; i < rules.items.size(); ++i) {
    auto rule = std::make_shared<Rule>();
    rule->id = in.text();
    rule->lhs = in.text();
    rule->rhs.resize(in.count(1));
    for (Symbol& s : rule->rhs) {
      s.type = static_cast<Symbol::Type>(in.below<std::uint8_t>(kSymbols));
      s.text = in.text();
    }
    rule->sem = nodes.ref(in);
    rule->induced = in.flag();
    rule->how = static_cast<RuleOrigin>(in.below<std::uint8_t>(kOrigins));
    rule->author = in.text();
    rule->head = in.text();
    rule->body.resize(in.count(sizeof(std::uint64_t)));
    for (std::string& line : rule->body) line = in.text();
    rule->created = in.get<std::int64_t>();
    rules.set(i, std::move(rule), 0);
  }
  Table<DerivationPtr> derivations(in.count(1));
  for (std::size_t i = 0; i < derivations.items.size(); ++i) {
    auto d = std::make_shared<Derivation>();
    d->rule = rules.ref(in);
    d->start = in.get<std::int32_t>();
    d->end = in.get<std::int32_t>();
    std::uint32_t deepest = 0;
    d->kids = derivations.refs(in, deepest);
    d->sem = nodes.ref(in);
    d->score = in.get<double>();
    d->core_only = in.flag();
    d->newest_rule = in.get<std::int64_t>();
    derivations.set(i, std::move(d), deepest);
  }
  ParseResult result;
  result.candidates.resize(in.count(1));
  for (Candidate& c : result.candidates) {
    c.program = nodes.ref(in);
    c.derivations = derivations.refs(in);
    c.score = in.get<double>();
    c.core_only = in.flag();
    c.newest_rule = in.get<std::int64_t>();
  }
  result.chart = derivations.refs(in);
  result.stopped = in.flag();
  result.derivations = in.get<std::uint64_t>();
  in.done();
  return result;
}

}  // namespace

std::optional<PathResult> path_result_of(std::string_view bytes) {
  return decoded<PathResult>(bytes, path_of);
}
std::optional<TourResult> tour_result_of(std::string_view bytes) {
  return decoded<TourResult>(bytes, tour_of);
}
std::string to_bytes(const std::vector<WeightChange>& values) {
  Bytes b;
  b.put<std::uint64_t>(values.size());
  for (const WeightChange& v : values) {
    b.put_text(v.model);
    b.put_text(v.feature);
    b.put(v.weight);
    b.put(v.aux);
  }
  return b.take();
}

std::optional<std::vector<WeightChange>> weight_values_of(std::string_view bytes) {
  return decoded<std::vector<WeightChange>>(bytes, [](std::string_view whole) {
    Reader in(whole);
    // Each value is at least two empty texts' lengths and two doubles.
    std::vector<WeightChange> values(in.count(std::size_t{4} * 8));
    for (WeightChange& v : values) {
      v.model = in.text();
      v.feature = in.text();
      v.weight = in.get<double>();
      v.aux = in.get<double>();
      if (!std::isfinite(v.weight) || !std::isfinite(v.aux)) throw Malformed{};
    }
    in.done();
    return values;
  });
}

bool learns_apart(const Scorer& scorer) {
  return dynamic_cast<const WeightValues*>(&scorer) != nullptr ||
         dynamic_cast<const IncrementalScorer*>(&scorer) == nullptr;
}

std::string learnt_bytes(const Scorer& scorer) {
  const auto* values = dynamic_cast<const WeightValues*>(&scorer);
  return values != nullptr ? to_bytes(values->pending_values()) : scorer.save_state();
}

bool apply_learnt(Scorer& scorer, std::string_view bytes) {
  auto* values = dynamic_cast<WeightValues*>(&scorer);
  if (values == nullptr) {
    scorer.load_state(bytes);
    return true;
  }
  const auto learnt = weight_values_of(bytes);
  if (learnt) values->set_values(*learnt);
  return learnt.has_value();
}

std::string to_bytes(const CallFailure& failure) {
  Bytes b;
  b.put(failure.cause);
  b.put_text(failure.code);
  b.put_text(failure.message);
  return b.take();
}

std::optional<CallFailure> call_failure_of(std::string_view bytes) {
  return decoded<CallFailure>(bytes, [](std::string_view whole) {
    Reader in(whole);
    CallFailure f;
    f.cause = in.get<std::uint64_t>();
    f.code = in.text();
    f.message = in.text();
    in.done();
    return f;
  });
}

std::optional<ParseResult> parse_result_of(std::string_view bytes) {
  return decoded<ParseResult>(bytes, parse_of);
}

}  // namespace host
}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
