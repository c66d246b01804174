#pragma once
// Study recording (docs/studio.md §7) in the corpus format `flipper replay` reads (as
// data/study2018/dev): queries.jsonl (one time-ordered line per participant action, each its own
// kind), worlds.jsonl (every world a command started or ended in), definitions.jsonl (the
// definitions with their induced rules, and group C's preloaded ones), original-answers.jsonl
// (the candidates each query showed, so an accept can be matched on replay), sessions.json,
// exchanges.jsonl (every protocol exchange, byte for byte, with the SHA-256 of its answer, for
// `flipper replay verify`), study.json (the study, the build and each group's effective config)
// and participants.json (participants.hpp). Each group is one run ("studio/<study>/<group>").
//
// Thread-safe: one mutex. The server calls record() inside the kernel's lock, so a group's
// records are in the order its kernel answered (docs/studio.md §5). Restart-safe: line and
// exchange numbers, participant ids, the rule map and the preload continue from the files.
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/session.hpp"
#include "flipper/record/durable_file.hpp"
#include "participants.hpp"

namespace flipper::studio {

struct SessionEntry;
class Study;

/// What the session told about the exchange being handled, from its typed events
/// (docs/architecture.md §3): the recorder learns what happened without parsing the answer.
/// Installed on every session of a study; record() reads it and clears it.
class RecorderTap : public kernel::SessionExtension {
 public:
  struct Candidate {
    std::string formula;
    bool induced = false;
  };
  struct Heard {
    bool answered = false;  ///< an op ran (RequestAnswered)
    std::string code;       ///< of a refusal ("" when ok)
    std::string status;     ///< a query's: "core", "induced", "unparsable"
    std::vector<Candidate> candidates;
    std::vector<sdk::RulePtr> rules;  ///< a definition's
  };
  void attach(kernel::Session& session) override;
  const Heard& heard() const { return heard_; }
  void clear() { heard_ = Heard(); }

 private:
  Heard heard_;
};

/// What a recorded exchange means for the HTTP reply.
struct RecordOutcome {
  bool goal_reached = false;  ///< an accept reached the task's goal (header Flipper-Goal)
};

class Recorder {
 public:
  /// Opens the recording folder (continuing a recording already there) and writes study.json
  /// when it has none. `kernels`: the groups' configs.
  Recorder(std::shared_ptr<Study> study,
           const std::vector<std::pair<std::string, kernel::Config>>& kernels);

  // -- participants (participants.json) --
  /// The participant an account already is.
  std::optional<ParticipantState> participant_of(const std::string& account);
  /// Whether new participants are taken.
  bool open();
  void set_open(bool open);
  /// A fresh participant id "P<n>"; `taken(name)`: the name is an account already.
  std::string next_id(const std::function<bool(const std::string&)>& taken);
  /// Enrolls an account: its group is `requested` when the study has it, else round robin.
  ParticipantState enroll(const std::string& account, const std::string& requested);

  // -- records --
  /// A protocol session opened for a participant: `session_start` (new) or `resume`.
  void session_started(const SessionEntry& entry, bool resumed);
  /// The world a resumed participant had (null: none yet).
  kernel::Json resume_world(const std::string& participant);
  /// One protocol exchange (after the session answered it, inside the kernel's lock).
  /// `origin`: "page" or "server" (requests the server made itself, e.g. resume).
  RecordOutcome record(const SessionEntry& entry, const std::string& request,
                       const std::string& answer, double ms, const char* origin = "page");
  /// A researcher's moderation (approve or reject, naturalization::moderation_request) in
  /// `group`'s kernel, as an exchange of origin "researcher" without participant or session,
  /// numbered in the kernel's order: call it inside that kernel's lock, after it applied.
  void record_moderation(const std::string& group, const std::string& account,
                         const std::string& request, const std::string& answer);
  /// A page event (flip, reject, page_load); the body was checked by the caller.
  void event(const SessionEntry& entry, const kernel::Json& body);

  // -- what the page and the researcher see --
  /// info.study's participant part: {participant, teaching, task, goal_reached, history}.
  kernel::Json page_state(const std::string& participant);
  /// The researcher's overview: participants and the files.
  kernel::Json overview();
  /// The recording's files a researcher may download.
  static const std::vector<std::string>& files();

  // -- the researcher's own actions (audit.jsonl, docs/studio.md §7 "Audit") --
  /// Appends one action of a researcher's account (close, reopen, invite, download) with the
  /// time and the peer address, synced before it returns: an acknowledged action is on record.
  /// `details` never holds a secret (an invitation's code is not written).
  void audit(const std::string& account, const std::string& peer, const std::string& action,
             const kernel::Json& details);

 private:
  struct Live {  ///< what a participant's session showed last (not kept across restarts)
    std::string last_qid, last_text;
    kernel::Json last_formulas = kernel::Json::array();
    int seq = 0;
    /// When the current task's task_start was recorded (this server run only): the goal and
    /// task_skip lines' task_ms (docs/studio.md §7 "Goals").
    std::optional<std::chrono::steady_clock::time_point> task_started;
  };
  /// A queries.jsonl line, its members in the order they are set (who, what, when first).
  using Line = nlohmann::ordered_json;
  std::string world_id(const SessionEntry& entry);
  Line line(const SessionEntry& entry, ParticipantState& p, const std::string& kind,
            std::optional<std::int64_t> exchange);
  /// Appends one exchanges.jsonl line (docs/studio.md §7), numbered `n`.
  void append_exchange(std::int64_t n, const std::string& group,
                       const nlohmann::ordered_json& participant,
                       const nlohmann::ordered_json& session, const std::string& user,
                       const std::string& qid, const char* origin, const std::string& request,
                       const std::string& answer);
  void write_sessions();
  void write_study_json(const std::vector<std::pair<std::string, kernel::Config>>& kernels);
  void load_existing();
  void preloaded(const std::string& group);
  ParticipantState& state(const SessionEntry& entry);
  bool goal_reached(const SessionEntry& entry, int task) const;
  /// Writes the queries.jsonl line(s) of one exchange; returns the qid of the main one ("").
  std::string command(const SessionEntry& entry, ParticipantState& p, const kernel::Json& request,
                      const RecorderTap::Heard& heard, double ms, std::int64_t exchange,
                      RecordOutcome& outcome);
  void define(const SessionEntry& entry, ParticipantState& p, const kernel::Json& request,
              const RecorderTap::Heard& heard, Line& c);

  std::mutex mutex_;
  std::shared_ptr<Study> study_;
  std::string dir_;
  record::AppendFile queries_, worlds_, definitions_, answers_, exchanges_, audit_;
  std::map<std::string, kernel::Json> worlds_by_id_;
  std::map<std::string, Live> live_;  ///< by participant
  kernel::Json sessions_ = kernel::Json::array();
  std::map<std::string, std::size_t> session_numbers_;  ///< by token: the sessions.json index
  std::set<std::string> preloaded_;                     ///< sources whose preload is written
  std::map<std::string, std::pair<std::string, int>> rule_defs_;  ///< rule id -> (def_id, pos)
  std::map<std::string, int> rule_lines_;                         ///< per source
  std::int64_t line_ = 0, exchange_ = 0;
  ParticipantStore participants_;
};

}  // namespace flipper::studio
