#pragma once
/// @file similarity.hpp
/// Similarity models: how alike two word sequences are (docs/naturalization.md §6), used by the
/// generalization step to prefer rewritings that read like the user's utterance.

#include <string>
#include <vector>

#include "flipper/sdk/export.hpp"
#include "flipper/sdk/plugin.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

class FLIPPER_SDK_API Similarity : public Plugin {
 public:
  using Interface = Similarity;
  ~Similarity() override;
  /// Similarity of two token sequences, in [-1, 1]; 0 when nothing is known. Never NaN.
  double similarity(const std::vector<std::string>& a, const std::vector<std::string>& b) const {
    return do_similarity(a, b);
  }

 protected:
  virtual double do_similarity(const std::vector<std::string>& a,
                               const std::vector<std::string>& b) const = 0;
};

template <>
struct KindOf<Similarity> {
  static constexpr PluginKind value = PluginKind::similarity;
};

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
