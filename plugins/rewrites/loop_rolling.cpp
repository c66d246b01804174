#include "loop_rolling.hpp"

#include <algorithm>
#include <vector>

namespace flipper::plugins::rewrites {

namespace {

using sdk::Kind;
using sdk::Program;

// The largest count a number token can carry (core-language §2.6).
constexpr std::size_t kMaxCount = 99;

Program roll_statement(const Program& p, std::size_t max_block);

bool blocks_equal(const std::vector<Program>& s, std::size_t a, std::size_t b, std::size_t k) {
  for (std::size_t j = 0; j < k; ++j)
    if (!sdk::equal(s[a + j], s[b + j])) return false;
  return true;
}

// Rolls an already statement-wise rolled list of statements into a program.
Program roll_list(const std::vector<Program>& s, std::size_t max_block) {
  const std::size_t n = s.size();
  std::vector<Program> out;
  out.reserve(n);
  std::size_t i = 0;
  while (i < n) {
    std::size_t best_k = 0, best_r = 1;
    const std::size_t k_max = std::min(max_block, (n - i) / 2);
    for (std::size_t k = 1; k <= k_max; ++k) {
      std::size_t r = 1;
      while (r < kMaxCount && i + (r + 1) * k <= n && blocks_equal(s, i, i + r * k, k)) ++r;
      if (r >= 2 && k * r > best_k * best_r) {
        best_k = k;
        best_r = r;
      }
    }
    if (best_r < 2) {
      out.push_back(s[i++]);
      continue;
    }
    std::vector<Program> block(s.begin() + static_cast<std::ptrdiff_t>(i),
                               s.begin() + static_cast<std::ptrdiff_t>(i + best_k));
    Program body = best_k == 1 ? block.front() : roll_list(block, max_block);
    out.push_back(sdk::make(Kind::Repeat, {sdk::make_num(static_cast<double>(best_r)), body}));
    i += best_k * best_r;
  }
  return sdk::make_seq(std::move(out));
}

// Rebuilds `p` with kid `index` replaced by its rolled form (p itself if unchanged).
Program roll_kid(const Program& p, std::size_t index, std::size_t max_block) {
  Program rolled = roll_statement(p->kids[index], max_block);
  if (rolled == p->kids[index]) return p;
  std::vector<Program> kids = p->kids;
  kids[index] = std::move(rolled);
  return sdk::make(p->kind, std::move(kids));
}

Program roll_statement(const Program& p, std::size_t max_block) {
  switch (p->kind) {
    case Kind::Seq: {
      std::vector<Program> stmts;
      stmts.reserve(p->kids.size());
      for (const auto& k : p->kids) stmts.push_back(roll_statement(k, max_block));
      Program rolled = roll_list(stmts, max_block);
      return sdk::equal(rolled, p) ? p : rolled;
    }
    case Kind::Strict:
      return roll_kid(p, 0, max_block);
    case Kind::ForeachPoint:
    case Kind::ForeachArea:
    case Kind::Repeat:
    case Kind::If:
    case Kind::While:
      return roll_kid(p, 1, max_block);
    default:
      return p;
  }
}

}  // namespace

Program roll_loops(const Program& program, std::size_t max_block) {
  if (!program || program->sort != sdk::Sort::Action || max_block == 0) return program;
  return roll_statement(program, max_block);
}

}  // namespace flipper::plugins::rewrites
