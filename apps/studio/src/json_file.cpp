#include "json_file.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "flipper/sdk/errors.hpp"

namespace flipper::studio {

std::optional<nlohmann::json> read_json_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return nlohmann::json::parse(text.str(), nullptr, false);
}

void write_json_file(const std::string& path, const nlohmann::json& value) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::trunc);
    if (!f) throw sdk::Error(sdk::codes::kInternal, "study: cannot write '" + tmp + "'");
    f << value.dump(1) << '\n';
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace flipper::studio
