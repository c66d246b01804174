// A moderation as a request and its answer (flipper/naturalization/moderation_request.hpp).
#include "flipper/naturalization/moderation_request.hpp"

#include <nlohmann/json.hpp>

#include "flipper/sdk/errors.hpp"

namespace flipper::naturalization {

using Json = nlohmann::json;

std::string moderation_request(bool approve, const std::string& id, const std::string& reason) {
  Json request{{"op", approve ? "approve" : "reject"}, {"id", id}};
  if (!approve && !reason.empty()) request["reason"] = reason;
  return request.dump();
}

std::string apply_moderation(Naturalizer& naturalizer, const std::string& moderator,
                             const std::string& request) {
  const Json r = Json::parse(request, nullptr, false);
  const bool well_formed = r.is_object() && r.contains("op") && r["op"].is_string() &&
                           r.contains("id") && r["id"].is_string() &&
                           (!r.contains("reason") || r["reason"].is_string());
  const std::string op = well_formed ? r["op"].get<std::string>() : std::string();
  if (op != "approve" && op != "reject")
    throw sdk::Error(sdk::codes::kBadRequest,
                     "a moderation is {\"op\":\"approve\"|\"reject\",\"id\":ID} (reject: and "
                     "\"reason\"), not " +
                         request.substr(0, 200));
  const std::string id = r["id"].get<std::string>();
  Json answer{{"ok", true}, {"op", op}, {"id", id}};
  if (op == "approve") {
    Json rules = Json::array();
    for (const auto& rule : naturalizer.approve(moderator, id)) rules.push_back(rule->id);
    answer["rules"] = std::move(rules);
  } else {
    naturalizer.reject(moderator, id, r.value("reason", std::string()));
  }
  return answer.dump();
}

}  // namespace flipper::naturalization
