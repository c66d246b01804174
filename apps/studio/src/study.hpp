#pragma once
// Study mode (serve.study: FILE): a study description drives the page through its tasks, and
// every participant is put in a group whose lexicon mode the study names (A: core, B: private,
// C: shared with the preloaded definitions), as in the 2018 study. docs/serve.md "Study mode".
//
//   name: pilot                      # names the recording's runs: studio/<name>/<group>
//   tutorial: "Tell the robot ..."   # shown before the first task
//   groups: [C]                      # participants are assigned round-robin (or ?group=)
//   preload: experts.jsonl           # group C's preloaded definitions (lexicon.preload format)
//   record: recording                # where the corpus is written (default: <name>-recording)
//   moderation: hold_new             # definitions wait for the researcher (default: the
//                                    # server's lexicon.moderation; docs/naturalization.md §5)
//   tasks:
//     - {name: warm-up, text: "Move the robot up.", start: worlds/a.json, goal: worlds/b.json}
//     - {name: red, text: "...", start: worlds/a.json, goal: {items: [{color: red, in: room4}]}}
// Relative paths resolve against the study file's directory.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "flipper/kernel/config.hpp"
#include "flipper/kernel/session.hpp"
#include "task_goal.hpp"

namespace flipper::studio {

struct StudyTask {
  std::string name;
  std::string text;
  kernel::Json start;  ///< world object
  TaskGoal goal;       ///< a world or a predicate (docs/studio.md §7 "Goals"); empty: none
};

class Study {
 public:
  /// Reads and checks the description. Throws sdk::Error(bad_config) naming the file and key.
  static std::shared_ptr<Study> load(const std::string& path);

  /// The kernels' configs: `base` with the group's lexicon mode and its own store in the
  /// recording directory.
  std::vector<std::pair<std::string, kernel::Config>> kernels(const kernel::Config& base) const;
  /// What the page shows: name, tutorial and tasks (the participant's part comes from the
  /// recorder; the group and its sharing mode are not shown: docs/studio.md §7).
  kernel::Json page_json() const;

  const std::string& name() const { return name_; }
  const std::string& record_dir() const { return record_dir_; }
  const std::string& preload() const { return preload_; }
  const std::vector<StudyTask>& tasks() const { return tasks_; }
  const std::vector<std::string>& groups() const { return groups_; }
  /// The recording's run for a group: "studio/<name>/<group>".
  std::string source(const std::string& group) const { return "studio/" + name_ + "/" + group; }

 private:
  std::string name_;
  std::string tutorial_;
  std::vector<std::string> groups_;
  std::string preload_;
  std::string record_dir_;
  std::string moderation_;  ///< lexicon.moderation for the groups ("": the server's)
  std::vector<StudyTask> tasks_;
};

/// The lexicon.sharing of a study group (A core, B private, C shared).
const char* sharing_of_group(const std::string& group);

}  // namespace flipper::studio
