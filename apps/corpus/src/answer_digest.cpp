#include "flipper/corpus/answer_digest.hpp"

#include <cctype>

namespace flipper::corpus {

std::string answer_for_digest(std::string_view answer) {
  static constexpr std::string_view kKey = ",\"ms\":";
  std::string out;
  out.reserve(answer.size());
  std::size_t at = 0;
  while (at < answer.size()) {
    const std::size_t hit = answer.find(kKey, at);
    if (hit == std::string_view::npos) break;
    std::size_t end = hit + kKey.size();
    const std::size_t digits = end + (end < answer.size() && answer[end] == '-' ? 1 : 0);
    if (digits >= answer.size() || !std::isdigit(static_cast<unsigned char>(answer[digits]))) {
      out.append(answer.substr(at, end - at));  // not a number: keep it
      at = end;
      continue;
    }
    end = digits;
    while (end < answer.size()) {
      const char c = answer[end];
      if (!std::isdigit(static_cast<unsigned char>(c)) && c != '.' && c != 'e' && c != 'E' &&
          c != '+' && c != '-')
        break;
      ++end;
    }
    out.append(answer.substr(at, hit - at));
    at = end;
  }
  out.append(answer.substr(at));
  return out;
}

}  // namespace flipper::corpus
