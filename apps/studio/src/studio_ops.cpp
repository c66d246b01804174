// The studio's ops over the session's op table (studio_ops.hpp).
#include "studio_ops.hpp"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "flipper/kernel/session_request.hpp"
#include "flipper/naturalization/naturalize_ops.hpp"
#include "flipper/sdk/errors.hpp"
#include "http_types.hpp"

namespace flipper::studio {
namespace fs = std::filesystem;
using kernel::Json;
using kernel::Session;
using toolkit::json::JsonWriter;

namespace {
// Measured (bench/serve, "memory"): a 2048 x 2048 grid2d world raises the server's resident
// memory by ~76 MiB with the planner's tables after a query on it: ~19 bytes per cell. Counted
// high, so the budget is never crossed.
constexpr std::size_t kBytesPerCell = 20;
}  // namespace

std::size_t world_bytes(std::size_t cells) {
  return cells * kBytesPerCell;
}

bool path_inside(const std::string& path, const std::string& root) {
  const fs::path p(path), r(root);
  auto pi = p.begin();
  for (auto ri = r.begin(); ri != r.end(); ++ri, ++pi) {
    if (ri->empty()) continue;  // a trailing separator of the root
    if (pi == p.end() || *pi != *ri) return false;
  }
  return true;
}

namespace {

// The error as a client may see it: no server path (docs/studio.md §2 "Messages").
sdk::Error client_error(const sdk::Error& e) {
  return sdk::Error(e.code(), without_paths(e.what()));
}

}  // namespace

void StudioOps::attach(Session& session) {
  // Every op reports whether it ran and what it threw (the HTTP status depends on the code).
  for (const auto& name : session.op_names()) {
    Session::OpHandler inner = *session.find_op(name);
    session.set_op(name, [this, inner](Session& s, const Json& r, JsonWriter& a) {
      op_ran_ = true;
      try {
        inner(s, r, a);
      } catch (const sdk::Error& e) {
        error_code_ = e.code();
        throw client_error(e);
      }
    });
  }
  const auto wrap = [&](const char* name, auto method) {
    const Session::OpHandler* found = session.find_op(name);
    if (found == nullptr) return;
    Session::OpHandler inner = *found;
    session.set_op(name, [this, inner, method](Session& s, const Json& r, JsonWriter& a) {
      op_ran_ = true;
      try {
        (this->*method)(s, r, a, inner);
      } catch (const sdk::Error& e) {
        error_code_ = e.code();
        throw client_error(e);
      }
    });
  };
  wrap("user", &StudioOps::op_user);
  wrap("world", &StudioOps::op_world);
  wrap("delete_rule", &StudioOps::op_delete_rule);
}

void StudioOps::op_user(Session& s, const Json& req, JsonWriter& a,
                        const Session::OpHandler& inner) {
  const std::string name = kernel::request::require_string(req, "name", "a user name");
  if (name != s.user())
    throw sdk::Error("forbidden", "over HTTP this session acts as '" + s.user() +
                                      "' (the account logged in, or the guest name it was "
                                      "given); log in as another account to act as it");
  inner(s, req, a);
}

void StudioOps::op_world(Session& s, const Json& req, JsonWriter& a,
                         const Session::OpHandler& inner) {
  const Json* forwarded = &req;
  Json resolved;
  // World files: only the config's world directory, resolved there (never the server's cwd).
  if (req.contains("file") && req["file"].is_string() &&
      (!req.contains("world") || req["world"].is_null())) {
    std::error_code ec;
    const fs::path file =
        fs::weakly_canonical(fs::path(context_.world_root) / req["file"].get<std::string>(), ec);
    if (ec || !path_inside(file.string(), context_.world_root))
      throw sdk::Error("forbidden",
                       "over HTTP a world file must be one of the server's worlds (info.worlds), "
                       "or send the world object in 'world'");
    resolved = req;
    resolved["file"] = file.string();
    forwarded = &resolved;
  }
  // The most this load can take is reserved first; what the world took is charged after.
  if (context_.reserve && !context_.reserve(context_.max_world_bytes))
    throw sdk::Error("server_busy",
                     "the server's memory for sessions is in use (serve.memory_budget_mb = " +
                         std::to_string(context_.budget_bytes >> 20) +
                         " MiB; a world may take up to " +
                         std::to_string(context_.max_world_bytes >> 20) + " MiB); try later");
  const auto charge_current = [&] {
    if (context_.charge)
      context_.charge(s.world().geometry ? world_bytes(s.world().geometry->cell_count()) : 0);
  };
  try {
    inner(s, *forwarded, a);
  } catch (...) {
    charge_current();
    throw;
  }
  charge_current();
}

void StudioOps::op_delete_rule(Session& s, const Json& req, JsonWriter& a,
                               const Session::OpHandler& inner) {
  const auto* ext = s.extension<naturalization::NaturalizationExtension>();
  if (context_.role == Role::admin && ext != nullptr) {
    naturalization::Naturalizer& nat = *ext->naturalizer();  // the current kernel's
    const std::string id = kernel::request::require_string(req, "rule", "a rule id");
    s.begin_call();
    nat.refresh();
    const sdk::RulePtr rule = nat.find_rule(id);
    if (rule && rule->author != s.user()) {
      // Moderation: deleted as its author would, the store's history keeps who wrote it.
      nat.delete_rule(rule->author, id);
      a.key("deleted").string(id);
      return;
    }
  }
  inner(s, req, a);
}

}  // namespace flipper::studio
