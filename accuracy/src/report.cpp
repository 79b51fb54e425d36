#include "rayspace/accuracy/report.h"

#include "rayspace/output_names.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "rayspace/plot.h"

namespace rayspace::accuracy {
namespace {

// ---- the plot: error rate against time per test, log-log ---------------------------------------------

// Error rates below this (and zero) are drawn on the bottom line, labelled "0 (none)".
constexpr double kFloorRate = 1e-7;

// The modes in the order of the rows, numbered from 1 per test and mode ("CGAL filtered" of the
// cone-sphere test is not that of the ray-triangle test): the table's # column and the plot's labels.
using ModeKey = std::pair<std::string, std::string>;  // test, mode
std::vector<ModeKey> ModeNumbers(const std::vector<Row>& rows) {
  std::vector<ModeKey> modes;
  for (const Row& r : rows)
    if (std::find(modes.begin(), modes.end(), ModeKey{r.test, r.mode}) == modes.end()) modes.push_back({r.test, r.mode});
  return modes;
}

std::size_t NumberOf(const std::vector<ModeKey>& modes, const Row& r) {
  return static_cast<std::size_t>(std::find(modes.begin(), modes.end(), ModeKey{r.test, r.mode}) - modes.begin()) + 1;
}

// One point per row and kind: the rate of `count` errors in n queries at the row's time per test.
plot::Point RatePoint(const Row& r, std::size_t count, std::size_t number) {
  const double n = static_cast<double>(std::max<std::size_t>(r.n, 1));
  return {std::max(r.ns, 1.0), std::max(static_cast<double>(count) / n, kFloorRate), fmt::format("{}", number)};
}

// Per row its false negatives (filled: a missed hit, a wrong image) and its false positives (open:
// an extra test, time only) apart, since a conservative test has FP by design and no FN; colour by
// test and query set, numbered by test and mode as in the table, the modes named in the key.
plot::Plot AccuracyPlot(const std::string& title, const std::vector<Row>& rows) {
  static const char* colours[6] = {"#d91a1a", "#1a59d9", "#1a9933", "#994db3", "#d9821a", "#1a9999"};
  plot::Plot p;
  p.title = title;
  p.width = 1100;
  p.x = {"ns per test (log)", plot::Scale::kLog, 1.0, 1e6, {}};
  p.y = {"errors per test against the exact answer (log)", plot::Scale::kLog, kFloorRate, 1.0, {}};
  p.y.ticks.push_back({kFloorRate, "0 (none)"});
  for (int e = 6; e >= 0; --e) p.y.ticks.push_back({std::pow(10.0, -e), fmt::format("1e-{}", e)});
  std::vector<std::string> keys;
  for (const Row& r : rows)
    if (std::find(keys.begin(), keys.end(), r.test + " / " + r.set) == keys.end()) keys.push_back(r.test + " / " + r.set);
  const std::vector<ModeKey> modes = ModeNumbers(rows);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    plot::Series fn{keys[k] + ": FN, missed hits (wrong image)", plot::Style::kPoints, plot::Marker::kFilledSquare, colours[k % 6], {}};
    plot::Series fp{keys[k] + ": FP, extra tests (time only)", plot::Style::kPoints, plot::Marker::kOpenSquare, colours[k % 6], {}};
    for (const Row& r : rows) {
      if (r.test + " / " + r.set != keys[k]) continue;
      fn.points.push_back(RatePoint(r, r.fn, NumberOf(modes, r)));
      fp.points.push_back(RatePoint(r, r.fp, NumberOf(modes, r)));
    }
    p.series.push_back(std::move(fn));
    p.series.push_back(std::move(fp));
  }
  // The zero line holds most modes: labels that would overlap are drawn once, joined.
  plot::MergeCloseLabels(p, 0.03);
  for (std::size_t m = 0; m < modes.size(); ++m)
    p.series.push_back({fmt::format("{}  {}: {}", m + 1, modes[m].first, modes[m].second), plot::Style::kPoints, plot::Marker::kNone,
                        "#000000", {}});
  return p;
}

// The table of modes: one row per mode and query set, numbered by test and mode as in the plot.
void AppendModeRows(const std::string& scene, const std::vector<Row>& rows, std::string& md, std::string& csv) {
  md += "| # | test | set | mode | queries | ns/test | FN | FP | of which in-plane |\n|---|---|---|---|---:|---:|---:|---:|---:|\n";
  const std::vector<ModeKey> modes = ModeNumbers(rows);
  for (const Row& r : rows) {
    md += fmt::format("| {} | {} | {} | {} | {} | {:.1f} | {} | {} | {} |\n", NumberOf(modes, r), r.test, r.set, r.mode, r.n, r.ns, r.fn,
                      r.fp, r.test == "ray-triangle" ? std::to_string(r.in_plane) : "-");
    csv += fmt::format("{},{},{},\"{}\",{},{:.2f},{},{},{},,,\n", scene, r.test, r.set, r.mode, r.n, r.ns, r.fn, r.fp, r.in_plane);
  }
}

// One end-to-end table (when measured): `kind` names the mode family in the CSV.
void AppendEndToEndTable(const std::vector<EndToEnd>& rows, const Report& rep, const char* kind, const char* caption,
                         const char* tests_column, std::string& md, std::string& csv) {
  if (rows.empty()) return;
  md += fmt::format("\n{}\n\n", caption);
  md += fmt::format("| mode | frame ms | {} | rays whose result changes |\n|---|---:|---:|---:|\n", tests_column);
  for (const EndToEnd& e : rows) {
    md += fmt::format("| {} | {:.0f} | {} | {} |\n", e.mode, e.ms, e.tests, e.changed);
    csv += fmt::format("{},{},end-to-end,\"{}\",,,,,,{:.1f},{},{}\n", rep.scene, kind, e.mode, e.ms, e.tests, e.changed);
  }
}

// The end-to-end tables, each when measured.
void AppendEndToEnd(const Report& rep, std::string& md, std::string& csv) {
  AppendEndToEndTable(rep.cone_e2e, rep, "cone-sphere",
                      "End to end, the frame with each cone-sphere mode in the traversal (all else equal), against the "
                      "exact traversal:",
                      "hierarchy tests", md, csv);
  AppendEndToEndTable(rep.tri_e2e, rep, "ray-triangle",
                      "End to end, the frame with each ray-triangle mode in the final tests (traversal conservative), "
                      "against exact hit decisions and exact distance order; a changed ray hits another primitive, hits "
                      "where the exact answer misses or the reverse, or changes occlusion (later bounces inherit the "
                      "differences):",
                      "final and hierarchy tests", md, csv);
  AppendEndToEndTable(rep.sphere_e2e, rep, "ray-sphere",
                      "End to end, the `--algo tl` frame with each ray-sphere mode in its walks, against the walks with "
                      "the exact test (a changed ray: another hit, or another occlusion):",
                      "sphere and triangle tests", md, csv);
  AppendEndToEndTable(rep.grid_e2e, rep, "grid-binning",
                      "End to end, the `--algo grid` frame with the binning's rounding margins and without them (each "
                      "triangle in the cells of its exact extent, least distances rounded to nearest), against the direct "
                      "tracer's frame (the same watertight test over every triangle; a changed ray: another hit, or another "
                      "occlusion):",
                      "triangle tests", md, csv);
}

}  // namespace

ReportFiles OpenReportFiles(const std::string& dir, const Scene& scene) {
  ReportFiles f;
  f.base = (std::filesystem::path(dir) / (SceneOutputStem(scene, "the report files are named after the scene: rename it") + "-accuracy")).string();
  f.md = OutputFile(f.base + ".md", {"the accuracy table", false, true, scene.files});
  f.csv = OutputFile(f.base + ".csv", {"the accuracy CSV", false, true, scene.files});
  f.svg = OutputFile(f.base + ".svg", {"the accuracy plot", false, true, scene.files});
  f.png = OutputFile(f.base + ".png", {"the accuracy plot", false, true, scene.files});
  return f;
}

void WriteReport(ReportFiles& files, const Report& rep) {
  const Workload& w = *rep.workload;
  std::string md = fmt::format("### {} ({}x{}, crsh)\n\nQueries sampled uniformly from the frame's own work: {} cone-sphere tests of {} and {} ray-triangle tests of {}; near-boundary sets move each sphere to touch the bundle (radius within 2^-20 of the distance) and aim each ray at an edge (2^-22 of the edge across it). FN: the mode says miss where the exact answer is hit (a missed hit changes the image); FP: the reverse (an extra test costs time only); the plot draws them apart, FN filled and FP open. The CSV holds this table and the end-to-end ones (set `end-to-end`, columns frame_ms, tests, rays_changed). Time: median of three passes, one thread.\n\n",
                               rep.scene, rep.width, rep.height, w.cones.size(), w.cones_seen, w.tris.size(), w.tris_seen);
  if (rep.spheres)
    md += fmt::format("The traversal lists' sphere test (`--algo tl`): {} of the {} ray-sphere tests of the same frame traced "
                      "with the lists; its near-boundary set moves each sphere to touch the ray's part (radius within 2^-20 of "
                      "the distance).\n\n",
                      rep.spheres->spheres.size(), rep.spheres->seen);
  // One header for both tables: a mode row fills the columns up to in_plane, an end-to-end row (set
  // "end-to-end") the last three.
  std::string csv = "scene,test,set,mode,queries,ns_per_test,false_negatives,false_positives,in_plane,frame_ms,tests,rays_changed\n";
  AppendModeRows(rep.scene, rep.rows, md, csv);
  AppendEndToEnd(rep, md, csv);
  files.md.Write(md);
  files.csv.Write(csv);
  const plot::Plot p = AccuracyPlot(fmt::format("{}: errors against time per test", rep.scene), rep.rows);
  for (auto [file, format] : {std::pair{&files.svg, plot::Format::kSvg}, std::pair{&files.png, plot::Format::kPng}}) {
    const std::vector<std::uint8_t> bytes = plot::Render(p, format);
    file->Write(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  }
  PublishAll({&files.md, &files.csv, &files.svg, &files.png});
  std::printf("%s\n  wrote %s.md, .csv, .svg, .png\n", md.c_str(), files.base.c_str());
}

}  // namespace rayspace::accuracy
