#pragma once
// Study recording in the corpus format `flipper replay` reads (as data/study2018/dev):
// queries.jsonl (q, accept, def commands), worlds.jsonl (every world a command started or ended
// in), definitions.jsonl (the definitions and group C's preloaded ones), original-answers.jsonl
// (the candidates each query showed, so an accept can be matched on replay) and sessions.json.
// Each group is one run ("studio/<study>/<group>"); statuses are written as the original's
// Core / Induced / Nothing. Lines are flushed as they are written.
#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "flipper/kernel/session.hpp"

namespace flipper::studio {

struct SessionEntry;
class Study;

class Recorder {
 public:
  /// Creates the directory and its files (appending to a recording already there).
  Recorder(std::shared_ptr<const Study> study);
  /// A participant joined (sessions.json) with the session's first world.
  void session_started(const SessionEntry& entry);
  /// One protocol exchange of a participant (after the session answered it).
  void record(const SessionEntry& entry, const kernel::Json& request, const std::string& answer,
              double ms);
  /// group C's preloaded definitions, written once per run.
  void preloaded(const std::string& group);

 private:
  struct Participant {
    std::string world_id;  ///< the world the session holds now
    std::string last_qid;
    std::string last_text;
    kernel::Json last_candidates;
    int seq = 0;
  };
  std::string world_id(const SessionEntry& entry);
  kernel::Json command(const SessionEntry& entry, Participant& p, const std::string& kind);
  void write(std::ofstream& out, const kernel::Json& line);
  void write_sessions();

  std::shared_ptr<const Study> study_;
  std::ofstream queries_, worlds_, definitions_, answers_;
  std::set<std::string> worlds_written_;
  std::map<std::string, Participant> participants_;  ///< by token
  kernel::Json sessions_ = kernel::Json::array();
  std::set<std::string> preloaded_;
  std::int64_t line_ = 0;
};

}  // namespace flipper::studio
