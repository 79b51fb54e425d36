// The report's files: report.md, tables/*.csv and results.json (byte-identical for one set of
// results), and timings.md and timings.csv (not).
#include <algorithm>

#include <fmt/format.h>

#include "rayspace/reproduce/report.h"
#include "rayspace/reproduce/fit_report.h"
#include "rayspace/json_text.h"
#include "rayspace/junit.h"
#include "rayspace/reproduce/roger.h"
#include "rayspace/reproduce/hunt.h"
#include "rayspace/reproduce/toczek.h"

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
std::vector<const Result*> TableOrder(std::vector<const Result*> sorted) {
  auto scene_rank = [](const std::string& scene) {
    for (std::size_t i = 0; i < ThesisScenes().size(); ++i)
      if (ThesisScenes()[i].paper == scene) return i;
    for (std::size_t i = 0; i < RogerScenes().size(); ++i)
      if (RogerScenes()[i].name == scene) return ThesisScenes().size() + i;
    for (std::size_t i = 0; i < ToczekScenes().size(); ++i)
      if (ToczekScenes()[i].name == scene) return ThesisScenes().size() + RogerScenes().size() + i;
    return ThesisScenes().size() + RogerScenes().size() + ToczekScenes().size();
  };
  std::sort(sorted.begin(), sorted.end(), [&](const Result* a, const Result* b) {
    // Every field of the configuration, so that no two results tie and the order never falls back
    // to the order of their keys.
    return std::make_tuple(a->config.target, scene_rank(a->config.scene), a->config.quadtree(), a->config.subdivision, a->config.levels,
                           a->config.algo, a->config.width, a->config.height, a->config.faithful, a->config.one_object, a->config.path,
                           a->config.lists, a->config.node_order, a->config.cull, a->config.heads, a->config.primary,
                           a->config.frustum, a->config.grid_area, a->config.grid_regular_cells) <
           std::make_tuple(b->config.target, scene_rank(b->config.scene), b->config.quadtree(), b->config.subdivision, b->config.levels,
                           b->config.algo, b->config.width, b->config.height, b->config.faithful, b->config.one_object, b->config.path,
                           b->config.lists, b->config.node_order, b->config.cull, b->config.heads, b->config.primary,
                           b->config.frustum, b->config.grid_area, b->config.grid_regular_cells);
  });
  return sorted;
}

std::vector<const Result*> TableOrder(const std::vector<Result>& results) {
  std::vector<const Result*> all;
  for (const Result& r : results) all.push_back(&r);
  return TableOrder(std::move(all));
}

}  // namespace

std::string ReportJUnit(const Report& report) {
  JUnitSuite suite{report.title, {}};
  for (const RelationRow& r : report.relations) {
    JUnitCase c;
    c.classname = "reproduce." + r.relation;
    c.name = r.where;
    c.output = "published: " + Verdict(r.published) + (r.published ? " (" + r.published->detail + ")" : "");
    if (!r.ours) {
      c.outcome = JUnitCase::Outcome::kSkipped;
      c.message = "not measured";
    } else if (!r.ours->holds) {
      c.outcome = JUnitCase::Outcome::kFailure;
      c.type = "relation";
      c.message = r.relation + " fails on ours: " + r.ours->detail;
      c.details = c.message + "\n" + c.output;
    }
    suite.cases.push_back(std::move(c));
  }
  return JUnitXml("rayspace reproduce", {suite});
}

Report WriteReport(const std::filesystem::path& out, const std::vector<Result>& results) {
  const Published& published = ThesisPublished();
  // Each target's sections from its own results: a run of roger alone has no thesis tables.
  std::vector<Result> thesis, ablation;
  std::vector<const Result*> roger, toczek, hunt;
  for (const Result& r : results)
    if (r.config.target == "thesis-ablation") ablation.push_back(r);
    else if (r.config.target == "roger") roger.push_back(&r);
    else if (r.config.target == "toczek") toczek.push_back(&r);
    else if (r.config.target == "hunt-mark") hunt.push_back(&r);
    else thesis.push_back(r);
  const std::vector<const Result*> sorted = TableOrder(results), roger_sorted = TableOrder(roger);
  Report report = thesis.empty() ? Report{} : BuildReport(thesis, published);
  if (!ablation.empty()) {
    for (Result& r : ablation) r.counts = SlotAccounting(r.counts, r.config.subdivision);
    if (thesis.empty()) report.title = "CRSH thesis: the faithful switches on SPONZA";
    report.tables.push_back(AblationTable(ablation, published));
  }
  if (thesis.empty() && ablation.empty()) {
    const int targets = !roger.empty() + !toczek.empty() + !hunt.empty();
    report.title = targets > 1 && hunt.empty() ? "Roger et al. 2007 and Toczek et al. 2010: the papers and ours"
                   : targets > 1              ? "The papers and ours"
                   : !hunt.empty()            ? "Hunt and Mark 2008: its tables and ours"
                   : !roger.empty()           ? "Roger et al. 2007: its claims and ours"
                                              : "Toczek et al. 2010: its tables and ours";
  }
  AddRogerReport(report, roger_sorted);
  AddToczekReport(report, TableOrder(toczek));
  Report hunt_timings;
  AddHuntReport(report, hunt_timings, TableOrder(hunt));
  for (Table& t : report.tables)
    if (const std::string plot = t.plot_x.empty() ? TablePlots(t, out) : SeriesPlot(t, out); !plot.empty()) t.notes.push_back(plot);
  std::filesystem::create_directories(out / "tables");
  for (const Table& t : report.tables) WriteText(out / "tables" / ("table-" + t.id + ".csv"), TableCsv(t), "a report table");
  if (!thesis.empty()) {
    WriteText(out / "tables" / "table-summary.csv", TableCsv(SummaryTable(report.relations)), "a report table");
    WriteText(out / "tables" / "table-summary-project.csv", TableCsv(SummaryTable(report.relations, false)), "a report table");
  }
  WriteText(out / "results.json", JsonText(ResultsJson(sorted)), "the results file");
  std::vector<const Result*> thesis_sorted;
  for (const Result* r : sorted)
    if (r->config.target == "thesis") thesis_sorted.push_back(r);
  Report timing_report;
  timing_report.preamble.push_back("Phase times vary run to run and from machine to machine: this file and timings.csv are "
                                   "not part of the reproducible report.");
  if (!thesis_sorted.empty()) timing_report.tables.push_back(TimingsTable(thesis_sorted, published));
  for (Table& t : RogerTimings(roger_sorted)) timing_report.tables.push_back(std::move(t));
  for (Table& t : hunt_timings.tables) {
    if (const std::string plot = SeriesPlot(t, out, "timing-plots"); !plot.empty()) t.notes.push_back(plot);
    timing_report.tables.push_back(std::move(t));
  }
  std::string csv;
  for (const Table& t : timing_report.tables) csv += (csv.empty() ? "" : "\n") + TableCsv(t);
  WriteText(out / "timings.csv", csv, "the timings file");
  std::string md = ReportMarkdown(timing_report);
  md.replace(0, md.find('\n'), "# Phase timings");
  WriteText(out / "timings.md", md, "the timings file");
  WriteText(out / "report.md", ReportMarkdown(report), "the report");
  return report;
}

}  // namespace rayspace::reproduce
