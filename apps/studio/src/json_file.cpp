#include "json_file.hpp"

#include <fstream>
#include <sstream>

#include "flipper/record/durable_file.hpp"

namespace flipper::studio {

std::optional<nlohmann::json> read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str(), nullptr, false);
}

void write_json_file(const std::string& path, const nlohmann::json& value) {
  record::write_file_atomically(path, value.dump(1) + "\n");
}

}  // namespace flipper::studio
