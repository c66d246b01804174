#pragma once
// The page's files, read into memory once at start-up: a GET is a map lookup, so no request
// path ever reaches the file system (no traversal, no symlink surprises).
#include <map>
#include <string>

namespace flipper::studio {

struct StaticFile {
  std::string content_type;
  std::string body;
};

class StaticFiles {
 public:
  /// Reads every regular file under `dir` (no symlinks followed), keyed "/relative/path".
  explicit StaticFiles(const std::string& dir);
  /// The file for a request path ("/" is "/index.html"), or null.
  const StaticFile* find(const std::string& path) const;
  std::size_t size() const { return files_.size(); }

 private:
  std::map<std::string, StaticFile, std::less<>> files_;
};

}  // namespace flipper::studio
