#include "bench_report.h"
#include "rayspace/frame/version.h"

#include <algorithm>
#include <map>
#include <optional>
#include <tuple>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/frame/text_table.h"

namespace rayspace::app {
namespace {

bool SameFrame(const BenchRow& a, const BenchRow& b) {
  return a.scene == b.scene && a.width == b.width && a.height == b.height;
}

// The baseline's row for the same scene and size, when it ran.
const BenchRow* BaselineRow(const std::vector<BenchRow>& rows, const BenchRow& row) {
  for (const BenchRow& b : rows)
    if (SameFrame(b, row) && b.config->name == kBaselineConfig && b.skipped.empty() && !b.frame_ms.empty()) return &b;
  return nullptr;
}

// Million tests per second over traversal + final tests; nullopt when the tests were not performed.
std::optional<double> MTestsPerSecond(const BenchRow& row) {
  const double ms = row.MedianSearchMs();
  if (!row.tests_performed || ms <= 0.0) return std::nullopt;
  return static_cast<double>(row.total_tests) / (ms * 1e3);
}

Cells TableRow(const std::vector<BenchRow>& rows, const BenchRow& r) {
  Cells c = {r.scene, r.Size(), r.config->name};
  if (!r.skipped.empty()) {
    c.push_back("skipped: " + r.skipped);
    return c;
  }
  const auto [lo, hi] = std::minmax_element(r.frame_ms.begin(), r.frame_ms.end());
  const BenchRow* base = BaselineRow(rows, r);
  const std::optional<double> rate = MTestsPerSecond(r);
  c.push_back(fmt::format("{:.1f}", r.MedianMs()));
  c.push_back(fmt::format("{:.1f}-{:.1f}", *lo, *hi));
  c.push_back(base ? fmt::format("{:.2f}", r.MedianMs() / base->MedianMs()) : "-");
  c.push_back(r.tests_counted ? Thousands(r.total_tests) : std::string("n/a"));
  c.push_back(rate ? fmt::format("{:.1f}", *rate) : "n/a");
  c.push_back(fmt::format("{:.1f}", static_cast<double>(r.peak_rss) / 1e6));
  c.push_back(r.peak_reset ? fmt::format("{:+.1f}", (static_cast<double>(r.peak_rss) - static_cast<double>(r.start_rss)) / 1e6)
                           : "-");
  c.push_back(r.digests.front());
  return c;
}

bool AllPeaksReset(const std::vector<BenchRow>& rows) {
  return std::all_of(rows.begin(), rows.end(), [](const BenchRow& r) { return r.peak_reset; });
}

void PrintNotes(std::FILE* out, const std::vector<BenchRow>& rows, int repetitions) {
  std::fprintf(out,
               "\nms: the frame's own time (render's `frame`), oracle off; median and range of %d repetition%s, run in\n"
               "  rounds (each round runs every configuration of a scene and size once).\n"
               "x %s: the median over %s's median for the same scene and size.\n"
               "M tests/s: total tests / (traversal + final tests time), as render --timings; n/a: brute and embree\n"
               "  report brute force (rays x triangles), not tests they perform.\n",
               repetitions, repetitions == 1 ? "" : "s", std::string(kBaselineConfig).c_str(),
               std::string(kBaselineConfig).c_str());
  if (AllPeaksReset(rows))
    std::fprintf(out, "peak MB: the process's peak resident memory over the configuration's repetitions (the peak is\n"
                      "  reset before each repetition; the loaded scene counts); MB added: that peak above what was\n"
                      "  resident when its repetition started.\n");
  else
    std::fprintf(out, "peak MB (process): the process's peak resident memory so far, not per configuration (the peak\n"
                      "  could not be reset: /proc/self/clear_refs is not writable here).\n");
}

// Adds "a and b agree" to the list of agreeing names that holds `a`, or starts one.
void AddAgreement(std::vector<std::vector<std::string>>& agreed, const std::string& a, const std::string& b) {
  for (std::vector<std::string>& names : agreed) {
    if (std::find(names.begin(), names.end(), a) == names.end()) continue;
    if (std::find(names.begin(), names.end(), b) == names.end()) names.push_back(b);
    return;
  }
  agreed.push_back({a, b});
}

// "a, b and c".
std::string Joined(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return s;
}

nlohmann::json RowJson(const std::vector<BenchRow>& rows, const BenchRow& r) {
  nlohmann::json j = {{"scene", r.scene},           {"width", r.width},
                      {"height", r.height},         {"config", r.config->name},
                      {"algorithm", r.config->algo}, {"path", r.config->path},
                      {"backend", r.config->backend},
                      {"render", r.config->render}};
  if (!r.skipped.empty()) {
    j["skipped"] = r.skipped;
    return j;
  }
  const BenchRow* base = BaselineRow(rows, r);
  const std::optional<double> rate = MTestsPerSecond(r);
  j["frame_ms"] = r.frame_ms;
  j["median_ms"] = r.MedianMs();
  j["ratio_to_" + std::string(kBaselineConfig)] = base ? nlohmann::json(r.MedianMs() / base->MedianMs()) : nlohmann::json();
  j["total_tests"] = r.tests_counted ? nlohmann::json(r.total_tests) : nlohmann::json(nullptr);
  j["tests_performed"] = r.tests_performed;
  j["search_ms"] = r.search_ms;
  j["traversal_ms"] = r.traversal_ms;
  j["mtests_per_s"] = rate ? nlohmann::json(*rate) : nlohmann::json();
  j["peak_rss_bytes"] = r.peak_rss;
  j["start_rss_bytes"] = r.start_rss;
  j["bytes_per_pixel"] = static_cast<double>(r.peak_rss) / static_cast<double>(r.Pixels());
  j["digests"] = r.digests;
  return j;
}

// The growth of a median time from one size to the next; "-" for tracers without that split (brute,
// embree) or without that phase.
std::string Growth(const BenchRow& from, const BenchRow& to, double (BenchRow::*median)() const) {
  if (!from.tests_performed || (from.*median)() <= 0.0) return "-";
  return fmt::format("x{:.2f}", (to.*median)() / (from.*median)());
}

}  // namespace

void PrintBenchTable(std::FILE* out, const std::vector<BenchRow>& rows, int repetitions) {
  const Cells header = {"scene", "size", "config", "median ms", "min-max ms", fmt::format("x {}", kBaselineConfig),
                        "total tests", "M tests/s", AllPeaksReset(rows) ? "peak MB" : "peak MB (process)", "MB added", "digest"};
  std::vector<Cells> cells;
  for (const BenchRow& r : rows) cells.push_back(TableRow(rows, r));
  PrintColumns(out, header, cells, {false, false, false, true, true, true, true, true, true, true, false});
  PrintNotes(out, rows, repetitions);
}

void PrintGrowthTable(std::FILE* out, const std::vector<BenchRow>& rows) {
  std::vector<Cells> cells;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const BenchRow& to = rows[i];
    if (!to.skipped.empty()) continue;
    // The same scene and configuration at the previous size, the nearest earlier such row.
    for (std::size_t j = i; j-- > 0;) {
      const BenchRow& from = rows[j];
      if (from.scene != to.scene || from.config != to.config || SameFrame(from, to)) continue;
      if (from.skipped.empty())
        cells.push_back({to.scene, to.config->name, from.Size() + " -> " + to.Size(),
                         fmt::format("x{:.3g}", static_cast<double>(to.Pixels()) / from.Pixels()),
                         fmt::format("x{:.2f}", to.MedianMs() / from.MedianMs()),
                         Growth(from, to, &BenchRow::MedianSearchMs), Growth(from, to, &BenchRow::MedianTraversalMs)});
      break;
    }
  }
  if (cells.empty()) return;
  std::fprintf(out,
               "\nTime growth with pixels (medians, from each size to the next; search: traversal + final tests; "
               "traversal: the hierarchy's levels alone):\n");
  PrintColumns(out, {"scene", "config", "sizes", "pixels", "frame", "search", "traversal"}, cells,
               {false, false, false, true, true, true, true});
}

bool CheckDigests(std::FILE* out, std::FILE* err, const std::vector<BenchRow>& rows) {
  bool ok = true;
  // Per scene, size, --algo and --levels (the levels change the statistics, which the digest holds).
  std::map<std::tuple<std::string, int, int, std::string, bool>, const BenchRow*> first;
  std::vector<std::vector<std::string>> agreed;  // per --algo and --levels, its configurations that gave the same digests
  for (const BenchRow& r : rows) {
    if (!r.skipped.empty() || r.digests.empty()) continue;
    const BenchRow*& ref = first[{r.scene, r.width, r.height, r.config->algo, r.config->levels_auto}];
    if (!ref) ref = &r;
    for (std::size_t k = 0; k < r.digests.size(); ++k) {
      if (r.digests[k] == ref->digests.front()) continue;
      ok = false;
      std::fprintf(err, "rayspace bench: error: %s %s: %s (repetition %zu) gave digest %s, %s gave %s; they must give the "
                   "same frame\n", r.scene.c_str(), r.Size().c_str(), r.config->name.c_str(), k + 1, r.digests[k].c_str(),
                   ref->config->name.c_str(), ref->digests.front().c_str());
    }
    if (ref != &r) AddAgreement(agreed, ref->config->name, r.config->name);
  }
  if (!ok) return false;
  for (const std::vector<std::string>& names : agreed)
    std::fprintf(out, "%s: one digest per scene and size, as required.\n", Joined(names).c_str());
  return true;
}

nlohmann::json BenchJson(const std::vector<BenchRow>& rows, int repetitions, int threads) {
  nlohmann::json results = nlohmann::json::array();
  for (const BenchRow& r : rows) results.push_back(RowJson(rows, r));
  nlohmann::json j = {{"repetitions", repetitions}, {"threads", threads}, {"peak_reset_per_config", AllPeaksReset(rows)},
                      {"results", results}};
  AddProvenance(j);
  return j;
}

}  // namespace rayspace::app
