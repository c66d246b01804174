#pragma once
// What the HTTP front end changes in a session, through the session's op table like every other
// front end (docs/architecture.md §3, kernel/session_extension.hpp): installed on each session
// the studio opens, after naturalization; the session attaches it again when it moves to another
// kernel of the pool (Session::rebind).
//   user         acts only as the session's own user (the account logged in, or the guest name);
//                another name is `forbidden` (docs/accounts.md)
//   world        a `file` must lie in the config's world directory (compared by path components,
//                so a sibling folder `<worlds>-x/` is outside); loading a world first reserves
//                the most a world may take from the server's memory budget (`server_busy` when
//                it cannot), then charges what the loaded world takes (docs/studio.md §4)
//   delete_rule  an administrator may delete anyone's rule (moderation)
// Every op also reports the error code it threw, so the front end maps answers to HTTP statuses
// without parsing them again.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include "flipper/kernel/session.hpp"
#include "flipper/kernel/session_extension.hpp"
#include "flipper/studio/accounts.hpp"

namespace flipper::studio {

/// Estimated bytes a world of `cells` cells holds in the server (docs/studio.md §4).
std::size_t world_bytes(std::size_t cells);

/// Whether `path` lies inside `root` (component by component, both canonical).
bool path_inside(const std::string& path, const std::string& root);

struct StudioOpsContext {
  std::string world_root;
  Role role = Role::user;
  std::size_t max_world_bytes = 0;  ///< the most one world may take (world.max_cells)
  std::size_t budget_bytes = 0;     ///< for messages
  /// Reserves bytes from the memory budget (false: no room); charges the session's total.
  std::function<bool(std::size_t)> reserve;
  std::function<void(std::size_t)> charge;
};

class StudioOps : public kernel::SessionExtension {
 public:
  explicit StudioOps(StudioOpsContext context) : context_(std::move(context)) {}
  void attach(kernel::Session& session) override;

  /// Call before each request; afterwards: whether an op handler ran and the code it threw.
  void reset() {
    op_ran_ = false;
    error_code_.clear();
  }
  bool op_ran() const { return op_ran_; }
  const std::string& error_code() const { return error_code_; }

 private:
  void op_user(kernel::Session& s, const kernel::Json& req, toolkit::json::JsonWriter& a,
               const kernel::Session::OpHandler& inner);
  void op_world(kernel::Session& s, const kernel::Json& req, toolkit::json::JsonWriter& a,
                const kernel::Session::OpHandler& inner);
  void op_delete_rule(kernel::Session& s, const kernel::Json& req, toolkit::json::JsonWriter& a,
                      const kernel::Session::OpHandler& inner);

  StudioOpsContext context_;
  bool op_ran_ = false;
  std::string error_code_;
};

}  // namespace flipper::studio
