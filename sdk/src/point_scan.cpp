#include "point_scan.hpp"

#include <algorithm>
#include <cstdint>

namespace flipper::sdk::detail {
namespace {

class PointScan {
 public:
  PointScan(std::string_view text, int dims) : t_(text), dims_(dims) {}

  std::optional<PointLists> run() {
    PointLists out;
    bool seen_walls = false, seen_rooms = false;
    skip_ws();
    if (!take('{')) return std::nullopt;
    skip_ws();
    if (take('}')) return std::nullopt;
    for (;;) {
      std::string_view key;
      if (!string(&key)) return std::nullopt;
      // "wa\u006cls" is "walls" too: a key with an escape is left to the full parse.
      if (key.find('\\') != std::string_view::npos) return std::nullopt;
      skip_ws();
      if (!take(':')) return std::nullopt;
      skip_ws();
      const std::size_t begin = p_;
      bool taken = false;
      if (key == "walls") {
        if (std::exchange(seen_walls, true)) return std::nullopt;  // the full parse names it
        std::vector<Cell> walls;
        if ((taken = point_list(walls))) {
          out.walls = std::move(walls);
          out.walls_at = {begin, p_};
        }
      } else if (key == "rooms") {
        if (std::exchange(seen_rooms, true)) return std::nullopt;
        std::vector<std::pair<std::string, std::vector<Cell>>> rooms;
        if ((taken = room_map(rooms))) {
          out.rooms = std::move(rooms);
          out.rooms_at = {begin, p_};
        }
      }
      if (!taken) {
        p_ = begin;
        if (!skip_value()) return std::nullopt;
      }
      skip_ws();
      if (take('}')) break;
      if (!take(',')) return std::nullopt;
      skip_ws();
    }
    if (!out.walls && !out.rooms) return std::nullopt;
    return out;
  }

 private:
  bool at_end() const { return p_ >= t_.size(); }
  bool take(char c) {
    if (at_end() || t_[p_] != c) return false;
    ++p_;
    return true;
  }
  void skip_ws() {
    while (!at_end() && (t_[p_] == ' ' || t_[p_] == '\t' || t_[p_] == '\n' || t_[p_] == '\r')) ++p_;
  }
  // A string at p_; `raw`: its bytes between the quotes, escapes as written.
  bool string(std::string_view* raw) {
    if (!take('"')) return false;
    const std::size_t start = p_;
    while (!at_end() && t_[p_] != '"') p_ += t_[p_] == '\\' ? 2 : 1;
    if (at_end()) return false;
    if (raw != nullptr) *raw = t_.substr(start, p_ - start);
    ++p_;
    return true;
  }
  // Past one value (not checked: the full parse of the rest does that): a string, a bracketed
  // value with strings inside, or a scalar up to the next ',' or '}'.
  bool skip_value() {
    int depth = 0;
    while (!at_end()) {
      const char c = t_[p_];
      if (c == '"') {
        if (!string(nullptr)) return false;
        if (depth == 0) return true;
        continue;
      }
      if (c == '{' || c == '[') {
        ++depth;
      } else if (c == '}' || c == ']') {
        if (depth == 0) return true;  // a scalar ended by the object's end
        if (--depth == 0) {
          ++p_;
          return true;
        }
      } else if (c == ',' && depth == 0) {
        return true;
      }
      ++p_;
    }
    return false;
  }
  // A JSON integer (-?(0|[1-9][0-9]*), no fraction or exponent) within ±2^28.
  bool integer(std::int32_t& out) {
    const bool negative = take('-');
    if (at_end() || t_[p_] < '0' || t_[p_] > '9') return false;
    std::int64_t v = 0;
    if (t_[p_] == '0') {
      ++p_;
    } else {
      while (!at_end() && t_[p_] >= '0' && t_[p_] <= '9') {
        v = v * 10 + (t_[p_++] - '0');
        if (v > kMaxCoordinate) return false;  // out of range: the full parse says so
      }
    }
    if (!at_end() &&
        (t_[p_] == '.' || t_[p_] == 'e' || t_[p_] == 'E' || (t_[p_] >= '0' && t_[p_] <= '9')))
      return false;
    out = static_cast<std::int32_t>(negative ? -v : v);
    return true;
  }
  // [[x, y], ...] (or [[x, y, z], ...] in 3-D).
  bool point_list(std::vector<Cell>& out) {
    if (!take('[')) return false;
    skip_ws();
    if (take(']')) return true;
    for (;;) {
      if (!take('[')) return false;
      std::int32_t xyz[3] = {0, 0, 0};
      for (int a = 0; a < dims_; ++a) {
        skip_ws();
        if (!integer(xyz[a])) return false;
        skip_ws();
        if (a + 1 < dims_ && !take(',')) return false;
      }
      if (!take(']')) return false;
      out.push_back({xyz[0], xyz[1], xyz[2]});
      skip_ws();
      if (take(']')) return true;
      if (!take(',')) return false;
      skip_ws();
    }
  }
  // {"name": [[x, y], ...], ...}: names that the full parse would read as written and accept.
  bool room_map(std::vector<std::pair<std::string, std::vector<Cell>>>& out) {
    if (!take('{')) return false;
    skip_ws();
    if (take('}')) return true;
    for (;;) {
      std::string_view name;
      if (!string(&name) || name.empty()) return false;
      for (const char c : name) {
        const auto b = static_cast<unsigned char>(c);
        if (b < 0x20 || b > 0x7e || c == '\\') return false;  // escapes, control bytes, UTF-8
      }
      skip_ws();
      if (!take(':')) return false;
      skip_ws();
      std::vector<Cell> points;
      if (!point_list(points)) return false;
      out.emplace_back(std::string(name), std::move(points));
      skip_ws();
      if (take('}')) break;
      if (!take(',')) return false;
      skip_ws();
    }
    // By name, as the tree's object has them; a duplicate is left to the full parse, which names
    // it.
    std::sort(out.begin(), out.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    return std::adjacent_find(out.begin(), out.end(), [](const auto& a, const auto& b) {
             return a.first == b.first;
           }) == out.end();
  }

  std::string_view t_;
  int dims_;
  std::size_t p_ = 0;
};

}  // namespace

std::optional<PointLists> scan_point_lists(std::string_view text, int dims) {
  return PointScan(text, dims).run();
}

}  // namespace flipper::sdk::detail
