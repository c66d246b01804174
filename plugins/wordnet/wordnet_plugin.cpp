// The `wordnet` similarity plugin: sentence similarity as the average best-match word
// similarity in both directions (Mihalcea et al. 2006 without idf weights), word similarity by
// Wu–Palmer over WordNet. Works offline with Debian's wordnet-base.
#include <algorithm>
#include <cmath>
#include <memory>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/similarity.hpp"
#include "word_similarity.hpp"
#include "wordnet_db.hpp"

namespace flipper::plugins::wordnet {

namespace {

constexpr sdk::param::Path kPath{"path", "/usr/share/wordnet",
                                 "WordNet 3.0 dictionary directory (index.noun, data.noun, ...)"};

}  // namespace

class WordNet : public sdk::Similarity {
 public:
  explicit WordNet(const sdk::Params& params)
      : db_(std::make_unique<WordNetDb>(sdk::param::get(params, kPath))), words_(*db_) {}

  static sdk::ParamSchema schema() { return sdk::param::schema(kPath); }

 protected:
  double do_similarity(const std::vector<std::string>& a,
                       const std::vector<std::string>& b) const override {
    if (a.empty() || b.empty()) return 0.0;
    const double s = 0.5 * (directed(a, b) + directed(b, a));
    return std::isfinite(s) ? std::clamp(s, 0.0, 1.0) : 0.0;
  }

 private:
  // Mean over the words of `from` of their best similarity to a word of `to`.
  double directed(const std::vector<std::string>& from, const std::vector<std::string>& to) const {
    double total = 0;
    for (const auto& w : from) {
      double best = 0;
      for (const auto& v : to) {
        best = std::max(best, words_(w, v));
        if (best >= 1.0) break;
      }
      total += best;
    }
    return total / static_cast<double>(from.size());
  }

  std::unique_ptr<WordNetDb> db_;
  WordSimilarity words_;
};

}  // namespace flipper::plugins::wordnet

FLIPPER_PLUGIN(flipper::plugins::wordnet::WordNet, similarity, "wordnet", FLIPPER_PLUGIN_VERSION,
               "Wu-Palmer word similarity over WordNet, best-match averaged (offline)")
