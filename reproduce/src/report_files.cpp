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

// The thesis's ms per frame of a phase of a scene's RAH or CRSH frame (tables 4.25-4.27), or -1.
double PublishedMs(const Published& p, const std::string& scene, const std::string& algorithm, const std::string& phase) {
  for (const PublishedTiming& t : p.timings)
    if (t.scene == scene && t.algorithm == algorithm && t.phase == phase) return t.total_ms_58_frames / 58.0;
  return -1.0;
}
// The same for a result: the tables' configuration is subdivision 8, depth 2.
double PublishedMs(const Published& p, const Result& r, const std::string& phase) {
  if (r.config.subdivision != 8 || r.config.levels != 2 || r.config.quadtree()) return -1.0;
  std::string alg = r.config.algo;
  for (char& c : alg) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return PublishedMs(p, r.config.scene, alg, phase);
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

// Tables 4.25-4.27 judged: the relations the thesis's text draws from them, at subdivision 8, depth 2,
// on ours (this run's phase times) and on the published times. Times: timings.md only.
Table TimingRelationsTable(const std::vector<const Result*>& sorted, const Published& p) {
  static const char* const kPhases[] = {"ray_creation", "ray_compression", "ray_sorting", "ray_decompression", "hierarchy_creation",
                                        "hierarchy_traversal", "final_intersection_tests"};
  Table t{"timings-relations", "Tables 4.25-4.27: the thesis's statements on its phase times, on ours and on the published",
          {"relation", "where", "ours", "compared", "published", "published compared", "source"}, {}, {}};
  const auto ours_ms = [](const Result& r, const std::string& phase) {
    for (const nlohmann::json& ph : r.timings.value("phases", nlohmann::json::array()))
      if (ph.value("phase", std::string()) == phase) return ph.value("ms", 0.0);
    return 0.0;
  };
  const auto verdict = [](bool holds) { return std::string(holds ? "holds" : "fails"); };
  for (const SceneChoice& sc : ThesisScenes()) {
    const Result* by_alg[2] = {nullptr, nullptr};
    for (const Result* r : sorted)
      if (r->config.scene == sc.paper && r->config.subdivision == 8 && r->config.levels == 2 && r->config.faithful.empty() &&
          r->config.switches.empty() && (r->config.algo == "rah" || r->config.algo == "crsh"))
        by_alg[r->config.algo == "crsh"] = r;
    for (int a = 0; a < 2; ++a) {
      const Result* r = by_alg[a];
      const std::string alg = a ? "CRSH" : "RAH";
      if (!r || PublishedMs(p, sc.paper, alg, "hierarchy_traversal") < 0) continue;
      // The largest of the seven phases, each side.
      std::string ours_top, pub_top;
      double ours_best = -1, pub_best = -1, ours_sum = 0, pub_sum = 0;
      for (const char* ph : kPhases) {
        const double o = ours_ms(*r, ph), q = PublishedMs(p, sc.paper, alg, ph);
        ours_sum += o, pub_sum += q;
        if (o > ours_best) ours_best = o, ours_top = ph;
        if (q > pub_best) pub_best = q, pub_top = ph;
      }
      const auto detail = [](const std::string& top, double best, double sum) {
        return fmt::format("largest: {} ({:.0f}% of the seven phases)", top, sum > 0 ? 100 * best / sum : 0.0);
      };
      t.rows.push_back({"the hierarchy traversal takes the largest share of the time", fmt::format("{} {} s8 d2", sc.paper, alg),
                        verdict(ours_top == "hierarchy_traversal"), detail(ours_top, ours_best, ours_sum),
                        verdict(pub_top == "hierarchy_traversal"), detail(pub_top, pub_best, pub_sum),
                        "4.4.14: \"the hierarchy traversal still takes up most of the rendering time\""});
    }
    if (by_alg[0] && by_alg[1] && PublishedMs(p, sc.paper, "CRSH", "hierarchy_traversal") >= 0) {
      const double o_rah = ours_ms(*by_alg[0], "hierarchy_traversal"), o_crsh = ours_ms(*by_alg[1], "hierarchy_traversal");
      const double p_rah = PublishedMs(p, sc.paper, "RAH", "hierarchy_traversal"), p_crsh = PublishedMs(p, sc.paper, "CRSH", "hierarchy_traversal");
      const auto cmp = [](double rah, double crsh) { return fmt::format("CRSH {:.1f} ms, RAH {:.1f} ms: x{:.2f}", crsh, rah, rah > 0 ? crsh / rah : 0.0); };
      t.rows.push_back({"CRSH traverses its hierarchy in less time than RAH", fmt::format("{} s8 d2", sc.paper), verdict(o_crsh < o_rah),
                        cmp(o_rah, o_crsh), verdict(p_crsh < p_rah), cmp(p_rah, p_crsh),
                        "tables 4.25-4.27's text, per scene (Sponza: \"we still manage to outperform RAH while traversing the hierarchy\")"});
    }
  }
  t.notes.push_back("Ours: this run's phase times on the emulator (the seven phases the thesis times; raster, shading and the rest "
                    "are left out of the shares). Published: the thesis's totals over 58 frames, per frame. Times vary run to run.");
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
                           a->config.frustum, a->config.grid_area, a->config.grid_regular_cells, a->config.threads, a->config.switches) <
           std::make_tuple(b->config.target, scene_rank(b->config.scene), b->config.quadtree(), b->config.subdivision, b->config.levels,
                           b->config.algo, b->config.width, b->config.height, b->config.faithful, b->config.one_object, b->config.path,
                           b->config.lists, b->config.node_order, b->config.cull, b->config.heads, b->config.primary,
                           b->config.frustum, b->config.grid_area, b->config.grid_regular_cells, b->config.threads, b->config.switches);
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
    if (Table fits = AblationFitsTable(ablation, published); !fits.rows.empty()) report.tables.push_back(std::move(fits));
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
  Report paper_timings;
  AddToczekReport(report, paper_timings, TableOrder(toczek));
  AddHuntReport(report, paper_timings, TableOrder(hunt));
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
  if (!thesis_sorted.empty()) {
    if (Table rel = TimingRelationsTable(thesis_sorted, published); !rel.rows.empty()) timing_report.tables.push_back(std::move(rel));
    timing_report.tables.push_back(TimingsTable(thesis_sorted, published));
  }
  for (Table& t : RogerTimings(roger_sorted)) timing_report.tables.push_back(std::move(t));
  for (Table& t : paper_timings.tables) {
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
