// The word lists the similarity compares (docs/naturalization.md §6).
#include <algorithm>
#include <array>
#include <string_view>

#include "flipper/naturalization/generalizer.hpp"
#include "flipper/sdk/canonical.hpp"

namespace flipper::naturalization {

namespace {

template <std::size_t N>
bool one_of(const std::string& token, const std::array<std::string_view, N>& list) {
  return std::find(list.begin(), list.end(), token) != list.end();
}

constexpr std::array<std::string_view, 5> kHeadPunctuation = {",", "[", "]", "{", "}"};
constexpr std::array<std::string_view, 12> kCandidateNoise = {
    "{", "}", "[", "]", ",", ";", "is", "containing", "in", "item", "items", "and"};

}  // namespace

std::vector<std::string> head_words(const std::vector<std::string>& head_tokens) {
  std::vector<std::string> out;
  out.reserve(head_tokens.size());
  for (const auto& t : head_tokens)
    if (!one_of(t, kHeadPunctuation)) out.push_back(t);
  return out;
}

std::vector<std::string> candidate_words(const sdk::Program& program) {
  std::vector<std::string> out;
  for (auto& t : sdk::tokenize(sdk::render(program)))
    if (!one_of(t, kCandidateNoise)) out.push_back(std::move(t));
  return out;
}

}  // namespace flipper::naturalization
