#include "participants.hpp"

#include "flipper/sdk/errors.hpp"
#include "json_file.hpp"

namespace flipper::studio {
using nlohmann::json;

ParticipantStore::ParticipantStore(std::string path) : path_(std::move(path)) {
  const std::optional<json> read = read_json_file(path_);
  if (!read) return;
  const json& j = *read;
  if (!j.is_object() || !j.contains("participants") || !j["participants"].is_array())
    throw sdk::Error(sdk::codes::kBadConfig,
                     "study: '" + path_ + "' is not a participants file (docs/studio.md §7)");
  open_ = j.value("open", true);
  next_ = j.value("next", 0);
  for (const auto& p : j["participants"]) {
    ParticipantState s;
    s.participant = p.value("participant", std::string());
    s.account = p.value("account", std::string());
    s.group = p.value("group", std::string());
    s.task = p.value("task", -1);
    s.goal_reached = p.value("goal_reached", false);
    s.history = p.value("history", json::array());
    s.world_id = p.value("world_id", std::string());
    s.counts = p.value("counts", std::map<std::string, int>());
    s.first_seen = p.value("first_seen", std::string());
    s.last_seen = p.value("last_seen", std::string());
    participants_.push_back(std::move(s));
  }
}

ParticipantState* ParticipantStore::find_account(const std::string& account) {
  for (auto& p : participants_)
    if (p.account == account) return &p;
  return nullptr;
}

ParticipantState* ParticipantStore::find(const std::string& participant) {
  for (auto& p : participants_)
    if (p.participant == participant) return &p;
  return nullptr;
}

ParticipantState& ParticipantStore::add(ParticipantState state) {
  participants_.push_back(std::move(state));
  return participants_.back();
}

void ParticipantStore::save() const {
  json list = json::array();
  for (const auto& p : participants_)
    list.push_back({{"participant", p.participant},
                    {"account", p.account},
                    {"group", p.group},
                    {"task", p.task},
                    {"goal_reached", p.goal_reached},
                    {"history", p.history},
                    {"world_id", p.world_id},
                    {"counts", p.counts},
                    {"first_seen", p.first_seen},
                    {"last_seen", p.last_seen}});
  write_json_file(path_, {{"open", open_}, {"next", next_}, {"participants", std::move(list)}});
}

}  // namespace flipper::studio
