#include "rayspace/reproduce/published.h"

#include <charconv>

#include "crsh_levels_csv.h"
#include "crsh_timings_csv.h"
#include "crsh_totals_csv.h"
#include "rayspace/error.h"

namespace rayspace::reproduce {
namespace {

// The CSV rows of `text` after its header, each split at commas (the files quote nothing).
std::vector<std::vector<std::string>> Rows(std::string_view text, const std::string& file, std::size_t columns) {
  std::vector<std::vector<std::string>> rows;
  std::size_t line_no = 0, start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (++line_no == 1 || line.empty()) continue;
    std::vector<std::string> cells;
    std::size_t from = 0;
    for (std::size_t comma; (comma = line.find(',', from)) != std::string_view::npos; from = comma + 1)
      cells.emplace_back(line.substr(from, comma - from));
    cells.emplace_back(line.substr(from));
    if (cells.size() != columns) ThrowInput("{}:{}: {} columns, expected {}", file, line_no, cells.size(), columns);
    rows.push_back(std::move(cells));
  }
  return rows;
}

template <typename T>
T Number(const std::string& cell, const std::string& file, std::size_t row, const char* column) {
  T v{};
  const auto [p, ec] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
  if (ec != std::errc() || p != cell.data() + cell.size())
    ThrowInput("{}: row {}: {} '{}' is not a number", file, row + 2, column, cell);
  return v;
}

}  // namespace

const std::uint64_t* Published::Level(HierarchyShape s, const std::string& scene, const std::string& algorithm,
                                      const std::string& ray_type, int level, const std::string& metric) const {
  const auto it = levels.find({s.subdivision, s.depth, scene, algorithm, ray_type, level, metric});
  return it == levels.end() ? nullptr : &it->second;
}

const std::pair<std::uint64_t, double>* Published::Total(HierarchyShape s, const std::string& scene,
                                                         const std::string& algorithm) const {
  const auto it = totals.find({s.subdivision, s.depth, scene, algorithm});
  return it == totals.end() ? nullptr : &it->second;
}

Published ParsePublished(std::string_view levels_csv, std::string_view totals_csv, std::string_view timings_csv,
                         const std::string& name) {
  Published p;
  const std::string lf = name + "crsh_levels.csv", tf = name + "crsh_totals.csv", mf = name + "crsh_timings.csv";
  const auto levels = Rows(levels_csv, lf, 8);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const auto& r = levels[i];
    p.levels[{Number<int>(r[0], lf, i, "subdivision"), Number<int>(r[1], lf, i, "depth"), r[2], r[3], r[4],
              Number<int>(r[5], lf, i, "level"), r[6]}] = Number<std::uint64_t>(r[7], lf, i, "count");
  }
  const auto totals = Rows(totals_csv, tf, 6);
  for (std::size_t i = 0; i < totals.size(); ++i) {
    const auto& r = totals[i];
    p.totals[{Number<int>(r[0], tf, i, "subdivision"), Number<int>(r[1], tf, i, "depth"), r[2], r[3]}] = {
        Number<std::uint64_t>(r[4], tf, i, "total_intersections"), Number<double>(r[5], tf, i, "relative_percent")};
  }
  const auto timings = Rows(timings_csv, mf, 6);
  for (std::size_t i = 0; i < timings.size(); ++i) {
    const auto& r = timings[i];
    p.timings.push_back({r[0], r[1], r[3], Number<double>(r[2], mf, i, "ms_per_frame"),
                         Number<double>(r[4], mf, i, "total_ms_58_frames"), Number<double>(r[5], mf, i, "relative_percent")});
  }
  if (p.levels.empty() || p.totals.empty()) ThrowInput("{}: no published rows", name);
  return p;
}

const Published& ThesisPublished() {
  static const Published p = ParsePublished(kCrshLevelsCsv, kCrshTotalsCsv, kCrshTimingsCsv);
  return p;
}

const PublishedScene& ThesisScene(const std::string& scene) {
  static const std::map<std::string, PublishedScene> scenes = {
      {"OFFICE", {251546, 0, 36308}}, {"CORNELL", {242015, 524288, 792}}, {"SPONZA", {256713, 0, 66450}}};
  const auto it = scenes.find(scene);
  RS_CHECK_MSG(it != scenes.end(), "no published frame for scene {}", scene);
  return it->second;
}

}  // namespace rayspace::reproduce
