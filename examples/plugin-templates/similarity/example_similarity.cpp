// example_similarity: the Jaccard overlap of two sentences' word sets, |A ∩ B| / |A ∪ B|, after
// leaving out the words of `ignore`; 0 when either is empty. Symmetric, in [0, 1], 1 for the same
// words, as the similarity contract asks (flipper/sdk/similarity.hpp).
#include <flipper/sdk/config_handles.hpp>
#include <flipper/sdk/plugin.hpp>
#include <flipper/sdk/similarity.hpp>

#include <algorithm>
#include <set>

namespace example_similarity {

namespace sdk = flipper::sdk;
namespace param = flipper::sdk::param;

constexpr param::TextList<4> kIgnore{
    "ignore", {"a", "an", "the", "to"}, "words left out before the sentences are compared"};

class ExampleSimilarity : public sdk::Similarity {
 public:
  explicit ExampleSimilarity(const sdk::Params& p) {
    for (const auto& word : param::get(p, kIgnore)) ignore_.insert(word);
  }
  static sdk::ParamSchema schema() { return param::schema(kIgnore); }

 protected:
  double do_similarity(const std::vector<std::string>& a,
                       const std::vector<std::string>& b) const override {
    const std::set<std::string> x = words(a), y = words(b);
    if (x.empty() || y.empty()) return 0.0;
    std::vector<std::string> both;
    std::set_intersection(x.begin(), x.end(), y.begin(), y.end(), std::back_inserter(both));
    const auto shared = static_cast<double>(both.size());
    return shared / (static_cast<double>(x.size() + y.size()) - shared);
  }

 private:
  std::set<std::string> words(const std::vector<std::string>& sentence) const {
    std::set<std::string> out;
    for (const auto& w : sentence)
      if (!ignore_.count(w)) out.insert(w);
    return out;
  }

  std::set<std::string> ignore_;
};

}  // namespace example_similarity

FLIPPER_PLUGIN(example_similarity::ExampleSimilarity, similarity, "example_similarity",
               FLIPPER_PLUGIN_VERSION, "Jaccard overlap of the two sentences' words")
