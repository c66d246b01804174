#pragma once
// A study's participants as the server keeps them across reloads, reopened tabs and restarts
// (docs/studio.md §7 "Participants and resume"): participants.json in the recording folder,
// rewritten atomically after every change and read back at start. Each participant is an
// account (enrolled as P<n>, or the login that arrived), with its group, task, whether the
// task's goal was reached, the history of accepted steps since the task started, the world the
// session holds (by worlds.jsonl id) and counts of what it did. Not thread-safe: the recorder
// calls it under its lock.
#include <chrono>
#include <deque>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flipper::studio {

struct ParticipantState {
  std::string participant;  ///< "P3": the id in every record
  std::string account;      ///< the account it acts as (its rules' author)
  std::string group;
  int task = -1;  ///< -1: the tutorial
  bool goal_reached = false;
  /// Accepted steps since the task started: {qid, utterance, formula, world_id,
  /// before_world_id[, steps]} (a step taught from history keeps the steps it replaced).
  nlohmann::json history = nlohmann::json::array();
  std::string world_id;
  std::map<std::string, int> counts;  ///< q, live, accept, reject, def, delete, undo, reset
  std::string first_seen, last_seen;  ///< ISO times
  std::chrono::steady_clock::time_point last_request{};  ///< not kept: "online" after a restart
};

class ParticipantStore {
 public:
  /// Reads `path` when it exists. Throws sdk::Error(bad_config) when it does not read.
  explicit ParticipantStore(std::string path);

  ParticipantState* find_account(const std::string& account);
  ParticipantState* find(const std::string& participant);
  /// The next free participant id ("P<n>", n counting from 1 across restarts); `taken` says
  /// whether a name is already used elsewhere (an account).
  template <class Taken>
  std::string next_id(Taken taken) {
    for (;;) {
      std::string id = "P" + std::to_string(++next_);
      if (!taken(id) && find(id) == nullptr) return id;
    }
  }
  ParticipantState& add(ParticipantState state);
  const std::deque<ParticipantState>& all() const { return participants_; }

  bool open() const { return open_; }
  void set_open(bool open) { open_ = open; }
  /// Rewrites the file (a temporary file renamed over it).
  void save() const;

 private:
  std::string path_;
  bool open_ = true;
  int next_ = 0;
  std::deque<ParticipantState> participants_;
};

}  // namespace flipper::studio
