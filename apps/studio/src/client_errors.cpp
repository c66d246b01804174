// What a client is told when something fails (http_types.hpp, docs/studio.md §2 "Messages"):
// never a server path, never a crashed server.
#include <iostream>
#include <mutex>

#include "flipper/sdk/errors.hpp"
#include "http_types.hpp"

namespace flipper::studio {
namespace {

bool starts_path(const std::string& text, std::size_t i) {
  if (text[i] != '/' || i + 1 >= text.size() || text[i + 1] == ' ') return false;
  if (i == 0) return true;
  const char before = text[i - 1];
  return before == ' ' || before == '\'' || before == '"' || before == '(' || before == '=' ||
         before == '`';
}

bool ends_path(char c) {
  return c == '\'' || c == '"' || c == ' ' || c == '\n' || c == ')' || c == '`' || c == ',';
}

}  // namespace

std::string without_paths(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  for (std::size_t i = 0; i < message.size();) {
    if (!starts_path(message, i)) {
      out.push_back(message[i++]);
      continue;
    }
    std::size_t end = i;
    while (end < message.size() && !ends_path(message[end])) ++end;
    const std::string path = message.substr(i, end - i);
    const auto slash = path.find_last_of('/');
    const std::string name = path.substr(slash + 1);
    out += name.empty() ? std::string("…") : name;
    i = end;
  }
  return out;
}

HttpReply answer_or_failure(const std::function<HttpReply()>& job) {
  try {
    return job();
  } catch (const sdk::Error& e) {
    static std::mutex log;
    {
      std::lock_guard lock(log);
      std::cerr << "flipper serve: [" << e.code() << "] " << e.what() << std::endl;
    }
    // A write the server could not make (a full disk, a read-only store): the request is not
    // acknowledged, and says so.
    if (e.code() == std::string(sdk::codes::kWriteFailed))
      return error_reply(503, e.code(),
                         "the server could not store this (" + std::string(e.what()) +
                             "); nothing was acknowledged: try again later");
    if (e.code() == "read_only") return error_reply(503, e.code(), e.what());
    return error_reply(500, e.code(), e.what());
  } catch (const std::exception& e) {
    std::cerr << "flipper serve: [internal] " << e.what() << std::endl;
    return error_reply(500, sdk::codes::kInternal, "the server failed to answer this request");
  }
}

}  // namespace flipper::studio
