// Fresh run folders and the `latest` link.
#include "flipper/record/run_folder.hpp"

#include <unistd.h>

#include <cctype>
#include <chrono>
#include <ctime>
#include <filesystem>

#include "flipper/record/checksum.hpp"
#include "flipper/sdk/errors.hpp"

namespace flipper::record {
namespace fs = std::filesystem;
namespace {

std::string utc_format(const char* format) {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[64];
  std::strftime(text, sizeof text, format, &tm);
  return text;
}

// Points PARENT/latest at `name`: a new link renamed over the old one (atomic), never over
// anything that is not a link (a user's own folder called `latest` stays).
void update_latest(const fs::path& parent, const std::string& name) {
  std::error_code ec;
  const fs::path latest = parent / "latest";
  if (fs::exists(fs::symlink_status(latest, ec)) && !fs::is_symlink(fs::symlink_status(latest, ec)))
    return;
  const fs::path temp = parent / (".latest-" + std::to_string(::getpid()));
  fs::remove(temp, ec);
  fs::create_directory_symlink(name, temp, ec);
  if (ec) return;
  fs::rename(temp, latest, ec);
  if (ec) fs::remove(temp, ec);
}

}  // namespace

std::string utc_now() {
  return utc_format("%Y-%m-%dT%H:%M:%SZ");
}

std::string directory_name(const std::string& name) {
  std::string out;
  for (char c : name)
    out += c == ',' ? '+'
           : std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' ||
                   c == '+' || c == '='
               ? c
               : '_';
  if (out.empty() || out == "." || out == "..") out = "_" + out;
  if (out.size() > 120) out = out.substr(0, 100) + "-" + sha256_text(name).substr(0, 12);
  return out;
}

bool is_run_folder(const std::string& dir) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(dir) / "manifest.json", ec);
}

void mark_latest(const std::string& run_dir) {
  const fs::path dir = fs::path(run_dir).lexically_normal();
  const fs::path name = dir.filename().empty() ? dir.parent_path().filename() : dir.filename();
  const fs::path parent =
      dir.filename().empty() ? dir.parent_path().parent_path() : dir.parent_path();
  update_latest(parent.empty() ? fs::path(".") : parent, name.string());
}

std::string create_run_folder(const std::string& parent, const std::string& stem) {
  if (is_run_folder(parent))
    throw sdk::Error(sdk::codes::kBadRequest,
                     "--out '" + parent +
                         "' is a run folder (it has a manifest.json); --out names the parent "
                         "folder under which each run creates its own");
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent))
    throw sdk::Error(sdk::codes::kBadRequest,
                     "cannot create the output folder '" + parent + "'" +
                         (ec ? ": " + ec.message() : std::string(": not a directory")));
  const std::string base = directory_name(stem) + "-" + utc_format("%Y%m%d-%H%M%S");
  for (int k = 1; k < 10000; ++k) {
    const std::string name = k == 1 ? base : base + "-" + std::to_string(k);
    const fs::path dir = fs::path(parent) / name;
    if (fs::create_directory(dir, ec)) return dir.string();
    if (ec)
      throw sdk::Error(sdk::codes::kBadRequest,
                       "cannot create the run folder '" + dir.string() + "': " + ec.message());
  }
  throw sdk::Error(sdk::codes::kBadRequest,
                   "cannot find a free run folder name '" + base + "-N' in '" + parent + "'");
}

}  // namespace flipper::record
