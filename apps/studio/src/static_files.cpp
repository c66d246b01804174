#include "static_files.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace flipper::studio {
namespace fs = std::filesystem;
namespace {

std::string content_type_of(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".ico") return "image/x-icon";
  return "application/octet-stream";
}

}  // namespace

StaticFiles::StaticFiles(const std::string& dir) {
  const fs::path root(dir);
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file() || entry.is_symlink()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    const std::string key = "/" + fs::relative(entry.path(), root).generic_string();
    files_[key] = StaticFile{content_type_of(entry.path()), text.str()};
  }
}

const StaticFile* StaticFiles::find(const std::string& path) const {
  auto it = files_.find(path == "/" ? std::string("/index.html") : path);
  return it == files_.end() ? nullptr : &it->second;
}

}  // namespace flipper::studio
