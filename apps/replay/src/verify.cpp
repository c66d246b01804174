// flipper replay verify: a study recording's exchanges replayed and compared byte for byte.
#include "flipper/replay/verify.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flipper/corpus/answer_digest.hpp"
#include "flipper/kernel/config.hpp"
#include "flipper/kernel/runtime.hpp"
#include "flipper/naturalization/moderation_request.hpp"
#include "flipper/record/checksum.hpp"
#include "flipper/replay/corpus.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/config_schema.hpp"
#include "flipper/wiring/session_factory.hpp"

namespace flipper::replay {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json read_json_file(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw sdk::Error(kBadCorpus, "'" + path.string() + "' is missing: not a studio recording");
  std::ostringstream text;
  text << in.rdbuf();
  json j = json::parse(text.str(), nullptr, false);
  if (j.is_discarded()) throw sdk::Error(kBadCorpus, "'" + path.string() + "' is not JSON");
  return j;
}

std::string text(const json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// The config dump without the server's keys and the store and preload lines (they differ by
// design: the replay keeps its store in memory and reads the recording's preload copy).
std::string comparable(const std::string& dump) {
  std::istringstream in(dump);
  std::string out, line, section;
  for (; std::getline(in, line);) {
    if (line.empty()) continue;
    if (line[0] != ' ') section = line;
    if (section == "serve:" || (section == "lexicon:" && (line.rfind("  path:", 0) == 0 ||
                                                          line.rfind("  preload:", 0) == 0)))
      continue;
    out += line + "\n";
  }
  return out;
}

// The value of `section.key` in a config dump ("" when absent): what the study chose for a group
// that the server's --config and --set do not say (study.cpp sets lexicon.moderation from it).
std::string dumped_value(const std::string& dump, const std::string& section,
                         const std::string& key) {
  std::istringstream in(dump);
  std::string line, current;
  const std::string prefix = "  " + key + ": ";
  for (; std::getline(in, line);) {
    if (!line.empty() && line[0] != ' ') current = line;
    if (current == section + ":" && line.rfind(prefix, 0) == 0) return line.substr(prefix.size());
  }
  return "";
}

std::size_t first_difference(const std::string& a, const std::string& b) {
  std::size_t i = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) ++i;
  return i;
}

}  // namespace

VerifyResult verify_recording(const std::string& dir, const VerifyOptions& options) {
  const json study = read_json_file(fs::path(dir) / "study.json");
  if (!study.is_object() || !study.contains("groups") || !study["groups"].is_object())
    throw sdk::Error(kBadCorpus, dir + "/study.json has no groups: not a studio recording");
  const fs::path exchanges = fs::path(dir) / "exchanges.jsonl";
  std::ifstream in(exchanges);
  if (!in) throw sdk::Error(kBadCorpus, "'" + exchanges.string() + "' is missing");

  VerifyResult result;
  std::map<std::string, std::unique_ptr<wiring::SessionHost>> groups;
  std::map<std::string, std::unique_ptr<kernel::Session>> sessions;  // by participant + session
  auto group_of = [&](const std::string& name) -> wiring::SessionHost& {
    auto& g = groups[name];
    if (g) return *g;
    const json recorded = study["groups"].value(name, json::object());
    const std::string sharing = text(recorded, "sharing");
    if (sharing.empty()) throw sdk::Error(kBadCorpus, "study.json names no group '" + name + "'");
    std::vector<std::string> sets = options.sets;
    const fs::path preload = fs::path(dir) / "preload-C.jsonl";
    sets.push_back("lexicon.sharing=" + sharing);
    const std::string moderation = dumped_value(text(recorded, "config"), "lexicon", "moderation");
    if (!moderation.empty()) sets.push_back("lexicon.moderation=" + moderation);
    sets.push_back("lexicon.path=:memory:");
    sets.push_back("lexicon.preload=" +
                   (name == "C" && fs::exists(preload) ? fs::absolute(preload).string() : ""));
    const kernel::Config config = wiring::load_config(options.config_file, sets);
    if (comparable(config.dump()) != comparable(text(recorded, "config")))
      result.notes.push_back("group " + name +
                             ": the effective config differs from the one study.json recorded "
                             "(give the server's --config and --set)");
    g = std::make_unique<wiring::SessionHost>(wiring::open_host(kernel::make_runtime(config)));
    return *g;
  };

  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    const json e = json::parse(line, nullptr, false);
    if (!e.is_object() || !e.contains("request") || !e["request"].is_string() ||
        !e.contains("answer") || !e["answer"].is_string())
      throw sdk::Error(kBadCorpus, exchanges.string() + ":" + std::to_string(n) +
                                       ": not an exchange {n, request, answer, sha256, ...}");
    const std::string group = text(e, "group"), participant = text(e, "participant");
    wiring::SessionHost& host = group_of(group);
    const std::string request = e["request"].get<std::string>();
    const std::string live = corpus::answer_for_digest(e["answer"].get<std::string>());
    std::string ours;
    if (text(e, "origin") == "researcher") {
      // A researcher's approve or reject, applied to the group's lexicon where it happened.
      if (!host.naturalizer)
        throw sdk::Error(kBadCorpus, exchanges.string() + ":" + std::to_string(n) +
                                         ": a moderation in a group without a lexicon");
      try {
        ours = naturalization::apply_moderation(*host.naturalizer, text(e, "user"), request);
      } catch (const sdk::Error& err) {
        ours = std::string("error ") + err.code() + ": " + err.what();
      }
    } else {
      const std::string key = participant + "#" + e.value("session", json()).dump();
      auto& session = sessions[key];
      if (!session) {
        session = host.open();
        session->set_user(text(e, "user"));
      }
      session->activate();
      ours = corpus::answer_for_digest(session->handle_line(request));
    }
    const json parsed = json::parse(request, nullptr, false);
    const std::string op = parsed.is_object() ? text(parsed, "op") : std::string();
    std::ostringstream where;
    where << "exchange " << e.value("n", json(n)).dump() << " ("
          << (participant.empty() ? "researcher " + text(e, "user") : "participant " + participant)
          << ", group " << group << ", qid " << e.value("qid", json()).dump() << ", op "
          << (op.empty() ? "?" : op) << ")";
    if (record::sha256_text(live) != text(e, "sha256")) {
      result.equal = false;
      result.divergence = where.str() +
                          ": the recorded answer does not match its recorded sha256 (the file "
                          "was changed)\nrequest: " +
                          request + "\nlive:    " + live + "\nreplay:  " + ours + "\n";
      return result;
    }
    if (ours != live) {
      result.equal = false;
      result.divergence = where.str() + " differs at byte " +
                          std::to_string(first_difference(live, ours)) + "\nrequest: " + request +
                          "\nlive:    " + live + "\nreplay:  " + ours + "\n";
      return result;
    }
    ++result.exchanges;
  }
  return result;
}

}  // namespace flipper::replay
