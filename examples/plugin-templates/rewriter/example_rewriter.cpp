// example_rewriter: proposes, for a body `repeat N times S` with a literal N of at most
// `max_unroll`, the same statement written out N times (`S; S; ...`). It only proposes: the kernel
// checks that a proposal does what the body does before it generalizes with it
// (docs/naturalization.md §6).
#include <flipper/sdk/ast.hpp>
#include <flipper/sdk/config_handles.hpp>
#include <flipper/sdk/plugin.hpp>
#include <flipper/sdk/rewriter.hpp>

#include <cmath>

namespace example_rewriter {

namespace sdk = flipper::sdk;
namespace param = flipper::sdk::param;

constexpr param::Int<int> kMaxUnroll{"max_unroll", 5, 1, 100, "largest repeat count written out"};

class ExampleRewriter : public sdk::Rewriter {
 public:
  explicit ExampleRewriter(const sdk::Params& p) : max_unroll_(param::get(p, kMaxUnroll)) {}
  static sdk::ParamSchema schema() { return param::schema(kMaxUnroll); }

 protected:
  std::vector<sdk::RewriteCandidate> do_propose(const sdk::RewriteRequest& req) const override {
    const sdk::Program& body = req.body;
    if (!body || body->kind != sdk::Kind::Repeat) return {};
    const sdk::Program& count = body->kids[0];
    if (count->kind != sdk::Kind::Num || count->number != std::floor(count->number) ||
        count->number < 1 || count->number > max_unroll_)
      return {};
    const std::vector<sdk::Program> copies(static_cast<std::size_t>(count->number), body->kids[1]);
    return {{copies.size() == 1 ? copies[0] : sdk::make_seq(copies), "unroll"}};
  }

 private:
  const int max_unroll_;
};

}  // namespace example_rewriter

FLIPPER_PLUGIN(example_rewriter::ExampleRewriter, rewriter, "example_rewriter",
               FLIPPER_PLUGIN_VERSION, "Writes out repeat loops with a small literal count")
