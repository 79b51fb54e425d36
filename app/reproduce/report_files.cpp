// The report's files: report.md, tables/*.csv and results.json (byte-identical for one set of
// results), and timings.md and timings.csv (not).
#include <algorithm>

#include <fmt/format.h>

#include "report.h"
#include "rayspace/json_text.h"

namespace rayspace::reproduce {
namespace {

// Every result without its timings, by key.
nlohmann::json ResultsJson(const std::vector<const Result*>& sorted) {
  nlohmann::json list = nlohmann::json::array();
  for (const Result* r : sorted) {
    nlohmann::json j = ToJson(*r);
    j.erase("timings");
    list.push_back(std::move(j));
  }
  return {{"version", Version()}, {"configurations", list}};
}

// The thesis's ms per frame of a phase (tables 4.25-4.27: subdivision 8, depth 2), or -1.
double PublishedMs(const Published& p, const Result& r, const std::string& phase) {
  if (r.config.subdivision != 8 || r.config.levels != 2 || r.config.quadtree()) return -1.0;
  std::string alg = r.config.algo;
  for (char& c : alg) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const PublishedTiming& t : p.timings)
    if (t.scene == r.config.scene && t.algorithm == alg && t.phase == phase) return t.total_ms_58_frames / 58.0;
  return -1.0;
}

Table TimingsTable(const std::vector<const Result*>& sorted, const Published& p) {
  Table t{"timings", "Phase timings (ours: this run, this machine; published: tables 4.25-4.27, GTX 770M, per frame)",
          {"scene", "configuration", "phase", "ours ms", "published ms"}, {}, {}};
  for (const Result* r : sorted) {
    if (!r->timings.contains("phases")) continue;
    for (const nlohmann::json& ph : r->timings["phases"]) {
      const std::string name = ph.value("phase", std::string());
      const double pub = PublishedMs(p, *r, name);
      t.rows.push_back({r->config.scene, r->config.Name(), name, fmt::format("{:.1f}", ph.value("ms", 0.0)),
                        pub < 0 ? "n/a" : fmt::format("{:.1f}", pub)});
    }
    t.rows.push_back({r->config.scene, r->config.Name(), "frame", fmt::format("{:.1f}", r->timings.value("frame_ms", 0.0)), "n/a"});
  }
  return t;
}

// In table order: by scene as the thesis lists them, then configuration.
std::vector<const Result*> TableOrder(const std::vector<Result>& results) {
  std::vector<const Result*> sorted;
  for (const Result& r : results) sorted.push_back(&r);
  auto scene_rank = [](const std::string& scene) {
    for (std::size_t i = 0; i < ThesisScenes().size(); ++i)
      if (ThesisScenes()[i].paper == scene) return i;
    return ThesisScenes().size();
  };
  std::sort(sorted.begin(), sorted.end(), [&](const Result* a, const Result* b) {
    return std::make_tuple(scene_rank(a->config.scene), a->config.quadtree(), a->config.subdivision, a->config.levels, a->config.algo) <
           std::make_tuple(scene_rank(b->config.scene), b->config.quadtree(), b->config.subdivision, b->config.levels, b->config.algo);
  });
  return sorted;
}

}  // namespace

void WriteReport(const std::filesystem::path& out, const std::vector<Result>& results) {
  const Published& published = ThesisPublished();
  Report report = BuildReport(results, published);
  for (Table& t : report.tables)
    if (const std::string plot = TablePlots(t, out); !plot.empty()) t.notes.push_back(plot);
  std::filesystem::create_directories(out / "tables");
  for (const Table& t : report.tables) WriteText(out / "tables" / ("table-" + t.id + ".csv"), TableCsv(t), "a report table");
  WriteText(out / "tables" / "table-summary.csv", TableCsv(SummaryTable(report.relations)), "a report table");
  const std::vector<const Result*> sorted = TableOrder(results);
  WriteText(out / "results.json", JsonText(ResultsJson(sorted)), "the results file");
  const Table timings = TimingsTable(sorted, published);
  WriteText(out / "timings.csv", TableCsv(timings), "the timings file");
  Report timing_report;
  timing_report.preamble.push_back("Phase times vary run to run and from machine to machine: this file and timings.csv are "
                                   "not part of the reproducible report.");
  timing_report.tables.push_back(timings);
  std::string md = ReportMarkdown(timing_report);
  md.replace(0, md.find('\n'), "# Phase timings");
  WriteText(out / "timings.md", md, "the timings file");
  WriteText(out / "report.md", ReportMarkdown(report), "the report");
}

}  // namespace rayspace::reproduce
