// The `glove` similarity plugin (docs/naturalization.md §6): cosine of the averaged word vectors of
// two token sequences. Unknown words contribute zero vectors; all-zero averages give 0.
#include <algorithm>
#include <cmath>
#include <memory>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/sdk/similarity.hpp"
#include "word_vectors.hpp"

namespace flipper::plugins::glove {

namespace {

namespace param = sdk::param;

constexpr param::Path kPath{
    "path", "", "word vectors in GloVe or word2vec text format (e.g. glove.6B.100d.txt)", true};
constexpr param::Int<std::size_t> kMaxWords{"max_words", 0, 0, std::nullopt,
                                            "read only the first N words of the file (0: all)"};

}  // namespace

class Glove : public sdk::Similarity {
 public:
  explicit Glove(const sdk::Params& params)
      : vectors_(std::make_shared<const WordVectors>(
            WordVectors::load(param::get(params, kPath), param::get(params, kMaxWords)))) {}

  static sdk::ParamSchema schema() { return param::schema(kPath, kMaxWords); }

 protected:
  double do_similarity(const std::vector<std::string>& a,
                       const std::vector<std::string>& b) const override {
    const std::size_t d = vectors_->dims();
    // The average and the sum point the same way, so summing is enough for the cosine.
    std::vector<double> sa(d, 0.0), sb(d, 0.0);
    sum(a, sa);
    sum(b, sb);
    double dot = 0, na = 0, nb = 0;
    for (std::size_t i = 0; i < d; ++i) {
      dot += sa[i] * sb[i];
      na += sa[i] * sa[i];
      nb += sb[i] * sb[i];
    }
    if (na <= 0 || nb <= 0) return 0.0;
    const double c = dot / (std::sqrt(na) * std::sqrt(nb));
    return std::isfinite(c) ? std::clamp(c, -1.0, 1.0) : 0.0;
  }

 private:
  void sum(const std::vector<std::string>& words, std::vector<double>& acc) const {
    for (const auto& w : words)
      if (const float* v = vectors_->find(w))
        for (std::size_t i = 0; i < acc.size(); ++i) acc[i] += v[i];
  }

  std::shared_ptr<const WordVectors> vectors_;
};

}  // namespace flipper::plugins::glove

FLIPPER_PLUGIN(flipper::plugins::glove::Glove, similarity, "glove", FLIPPER_PLUGIN_VERSION,
               "Cosine of averaged GloVe/word2vec vectors (the original's similarity)")
