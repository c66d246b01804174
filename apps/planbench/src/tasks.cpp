// Benchmark tasks and the breadth-first oracle (docs/planners.md §5).
#include "flipper/planbench/tasks.hpp"

#include <yaml-cpp/yaml.h>

#include <deque>
#include <limits>

#include "flipper/sdk/errors.hpp"
#include "flipper/wiring/yaml_file.hpp"

namespace flipper::planbench {

std::optional<std::size_t> shortest_steps(const sdk::Geometry& g, sdk::Cell start, sdk::Cell goal) {
  if (!g.is_free(start) || !g.is_free(goal)) return std::nullopt;
  if (start == goal) return 0;
  constexpr std::size_t kUnseen = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> dist(g.cell_count(), kUnseen);
  std::deque<sdk::Cell> queue{start};
  dist[g.index(start)] = 0;
  while (!queue.empty()) {
    const sdk::Cell c = queue.front();
    queue.pop_front();
    const std::size_t d = dist[g.index(c)];
    for (const sdk::Cell& step : g.neighbour_offsets()) {
      const sdk::Cell n = c + step;
      if (!g.is_free(n) || dist[g.index(n)] != kUnseen) continue;
      if (n == goal) return d + 1;
      dist[g.index(n)] = d + 1;
      queue.push_back(n);
    }
  }
  return std::nullopt;
}

namespace {

sdk::Cell read_cell(const YAML::Node& node, int dims, const std::string& where) {
  if (!node || !node.IsSequence() || static_cast<int>(node.size()) != dims)
    throw sdk::Error(sdk::codes::kBadConfig,
                     where + "must be a cell of " + std::to_string(dims) + " integers");
  sdk::Cell c;
  c.x = node[0].as<std::int32_t>();
  c.y = node[1].as<std::int32_t>();
  if (dims == 3) c.z = node[2].as<std::int32_t>();
  return c;
}

}  // namespace

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::vector<Task> random_tasks(const sdk::Geometry& g, int count, std::uint64_t seed) {
  std::vector<Task> tasks;
  const sdk::Area& free = g.free_cells();
  if (free.size() < 2) return tasks;
  std::uint64_t state = seed;
  const std::uint64_t n = free.size();
  for (long draws = 0; static_cast<int>(tasks.size()) < count && draws < 1000L * count; ++draws) {
    const sdk::Cell s = free[splitmix64(state) % n], t = free[splitmix64(state) % n];
    if (s == t) continue;
    const auto steps = shortest_steps(g, s, t);
    if (!steps) continue;
    tasks.push_back({"t" + std::to_string(tasks.size() + 1), s, t, steps});
  }
  return tasks;
}

std::vector<Task> read_task_file(const std::string& path, const sdk::Geometry& g) {
  const std::string where = "task file '" + path + "': ";
  const YAML::Node root = wiring::load_bounded_yaml_file(path, "task file");
  std::vector<Task> tasks;
  try {
    const YAML::Node list = root["tasks"];
    if (!list || !list.IsSequence() || list.size() == 0)
      throw sdk::Error(sdk::codes::kBadConfig,
                       where + "needs 'tasks: [{name, start: [x, y], goal: [x, y]}, ...]'");
    for (std::size_t i = 0; i < list.size(); ++i) {
      Task t;
      t.name = list[i]["name"] ? list[i]["name"].as<std::string>() : "t" + std::to_string(i + 1);
      const std::string at = where + "task '" + t.name + "' ";
      for (const auto& kv : list[i]) {
        const auto key = kv.first.as<std::string>();
        if (key != "name" && key != "start" && key != "goal")
          throw sdk::Error(sdk::codes::kBadConfig,
                           at + "has unknown key '" + key + "' (keys: name, start, goal)");
      }
      t.start = read_cell(list[i]["start"], g.dims(), at + "'start' ");
      t.goal = read_cell(list[i]["goal"], g.dims(), at + "'goal' ");
      for (const auto& [what, c] : {std::pair{"start", t.start}, std::pair{"goal", t.goal}})
        if (!g.is_free(c))
          throw sdk::Error(sdk::codes::kBadConfig, at + "'" + what + "' " +
                                                       sdk::to_string(c, g.dims()) +
                                                       " is not a free cell of the world");
      for (const auto& other : tasks)
        if (other.name == t.name)
          throw sdk::Error(sdk::codes::kBadConfig, where + "two tasks are named '" + t.name + "'");
      t.shortest = shortest_steps(g, t.start, t.goal);
      tasks.push_back(std::move(t));
    }
  } catch (const YAML::Exception& ex) {
    throw sdk::Error(sdk::codes::kBadConfig, where + ex.what());
  }
  return tasks;
}

std::vector<Task> tasks_for(const TaskSource& source, const sdk::Geometry& g) {
  if (!source.file.empty()) return read_task_file(source.file, g);
  return random_tasks(g, source.random, source.seed);
}

}  // namespace flipper::planbench
