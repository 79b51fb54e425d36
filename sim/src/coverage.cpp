#include "rayspace/sim/coverage.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <utility>

#include <fmt/format.h>

namespace rayspace::sim {

LineCoverage CoverageOf(const Program& program, std::span<const std::uint8_t> executed) {
  LineCoverage c;
  // (file, line) -> reached.
  std::map<std::pair<std::uint32_t, std::uint32_t>, bool> lines;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> order;
  for (std::size_t i = 0; i < program.code.size(); ++i) {
    const Inst& in = program.code[i];
    const bool ran = i < executed.size() && executed[i] != 0;
    if (!in.line) continue;
    const auto key = std::make_pair(in.file, in.line);
    const auto [it, fresh] = lines.emplace(key, ran);
    if (fresh) order.push_back(key);
    it->second = it->second || ran;
  }
  if (lines.empty()) {  // no debug information: instructions
    c.by_line = false;
    c.total = program.code.size();
    for (std::size_t i = 0; i < program.code.size(); ++i) c.reached += i < executed.size() && executed[i] != 0;
    return c;
  }
  c.total = lines.size();
  std::sort(order.begin(), order.end());
  const auto file_of = [&program](std::uint32_t id) {
    const auto f = program.strings.find(id);
    return f == program.strings.end() ? std::string("line") : std::filesystem::path(f->second).filename().string();
  };
  for (std::size_t k = 0; k < order.size();) {
    if (lines[order[k]]) {
      ++c.reached;
      ++k;
      continue;
    }
    // A run of unreached lines of one file, consecutive among the lines that carry code.
    std::size_t e = k;
    while (e + 1 < order.size() && order[e + 1].first == order[k].first && !lines[order[e + 1]]) ++e;
    const std::string file = file_of(order[k].first);
    c.missed.push_back(e == k ? fmt::format("{}:{}", file, order[k].second)
                              : fmt::format("{}:{}-{}", file, order[k].second, order[e].second));
    k = e + 1;
  }
  return c;
}

}  // namespace rayspace::sim
