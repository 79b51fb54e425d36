#include "accuracy_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/image_io.h"

namespace rayspace::app::accuracy {
namespace {

// ---- the plot: error rate against time per test, log-log ---------------------------------------------

// The rows' markers: per row its false negatives (filled: a missed hit, a wrong image) and its false
// positives (open: an extra test, time only) apart, since a conservative test has FP by design and no
// FN; colour by test and query set, numbered by mode as in the table.
template <typename XF, typename YF, typename TextF>
void PlotRows(OIIO::ImageBuf& img, const std::vector<Row>& rows, XF X, YF Y, TextF text) {
  using namespace OIIO;
  const int W = img.spec().width, R = 330, T = 70;
  const float black[3] = {0, 0, 0};
  const float colours[4][3] = {{0.85f, 0.1f, 0.1f}, {0.1f, 0.35f, 0.85f}, {0.1f, 0.6f, 0.2f}, {0.6f, 0.3f, 0.7f}};
  std::vector<std::string> keys, modes;
  for (const Row& r : rows) {
    if (std::find(keys.begin(), keys.end(), r.test + " / " + r.set) == keys.end()) keys.push_back(r.test + " / " + r.set);
    if (std::find(modes.begin(), modes.end(), r.mode) == modes.end()) modes.push_back(r.mode);
  }
  for (const Row& r : rows) {
    const int k = static_cast<int>(std::find(keys.begin(), keys.end(), r.test + " / " + r.set) - keys.begin()) % 4;
    const std::size_t m = std::find(modes.begin(), modes.end(), r.mode) - modes.begin();
    const double n = static_cast<double>(std::max<std::size_t>(r.n, 1));
    const int x = X(r.ns), y_fn = Y(static_cast<double>(r.fn) / n), y_fp = Y(static_cast<double>(r.fp) / n);
    ImageBufAlgo::render_box(img, x - 4, y_fn - 4, x + 4, y_fn + 4, colours[k], true);
    ImageBufAlgo::render_box(img, x - 5, y_fp - 5, x + 5, y_fp + 5, colours[k], false);
    ImageBufAlgo::render_box(img, x - 4, y_fp - 4, x + 4, y_fp + 4, colours[k], false);
    text(x + 7, y_fn - 6, fmt::format("{}", m + 1), 11, black);
    if (y_fp != y_fn) text(x + 7, y_fp - 6, fmt::format("{}", m + 1), 11, black);
  }
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const int y = T + 20 + static_cast<int>(k) * 22;
    ImageBufAlgo::render_box(img, W - R + 15, y - 10, W - R + 25, y, colours[k % 4], true);
    text(W - R + 32, y, keys[k], 14, black);
  }
  const int key_y = T + 20 + static_cast<int>(keys.size()) * 22;
  ImageBufAlgo::render_box(img, W - R + 15, key_y - 10, W - R + 25, key_y, black, true);
  text(W - R + 32, key_y, "FN: missed hits (wrong image)", 12, black);
  ImageBufAlgo::render_box(img, W - R + 15, key_y + 10, W - R + 25, key_y + 20, black, false);
  text(W - R + 32, key_y + 20, "FP: extra tests (time only)", 12, black);
  for (std::size_t m = 0; m < modes.size(); ++m) {
    const int y = key_y + 45 + 20 * static_cast<int>(m);
    text(W - R + 2, y, fmt::format("{}", m + 1), 12, black);
    text(W - R + 15, y, modes[m], 12, black);
  }
}

void Plot(OutputFile& file, const std::string& title, const std::vector<Row>& rows) {
  using namespace OIIO;
  const int W = 900, H = 620, L = 90, R = 330, T = 70, B = 70;
  ImageBuf img(ImageSpec(W, H, 3, TypeDesc::UINT8));
  const float white[3] = {1, 1, 1}, black[3] = {0, 0, 0}, grey[3] = {0.85f, 0.85f, 0.85f};
  ImageBufAlgo::fill(img, white);
  const std::string font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  bool text_ok = true;
  auto text = [&](int x, int y, const std::string& s, int size, const float* c) {
    text_ok = ImageBufAlgo::render_text(img, x, y, s, size, font, c) && text_ok;
  };
  // x: log10(ns) in [0, 6]; y: log10(error rate) in [-7, 0], zero errors drawn on the bottom line.
  auto X = [&](double ns) { return L + static_cast<int>((std::log10(std::max(ns, 1.0)) / 6.0) * (W - L - R)); };
  auto Y = [&](double rate) {
    const double lr = rate > 0 ? std::max(std::log10(rate), -7.0) : -7.0;
    return T + static_cast<int>((-lr / 7.0) * (H - T - B));
  };
  for (int d = 0; d <= 6; ++d) {
    ImageBufAlgo::render_line(img, X(std::pow(10, d)), T, X(std::pow(10, d)), H - B, grey);
    text(X(std::pow(10, d)) - 12, H - B + 22, fmt::format("1e{}", d), 14, black);
  }
  for (int e = 0; e <= 7; ++e) {
    ImageBufAlgo::render_line(img, L, Y(std::pow(10, -e)), W - R, Y(std::pow(10, -e)), grey);
    text(L - 55, Y(std::pow(10, -e)) + 5, e == 7 ? "0 (none)" : fmt::format("1e-{}", e), 14, black);
  }
  ImageBufAlgo::render_box(img, L, T, W - R, H - B, black);
  text(10, 24, title, 18, black);
  text(10, T - 16, "errors per test against the exact answer (log): FN filled, FP open", 14, black);
  text((W - R) / 2 - 40, H - 15, "ns per test (log)", 15, black);
  PlotRows(img, rows, X, Y, text);
  if (!text_ok) std::fprintf(stderr, "rayspace accuracy: warning: no font at %s (install fonts-dejavu-core); the plot has no labels\n", font.c_str());
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(W) * H * 3);
  if (!img.get_pixels(img.roi(), TypeDesc::UINT8, rgb.data())) ThrowInput("{}: cannot draw the plot ({})", file.path(), img.geterror());
  WriteImage(file, W, H, rgb);
}

// The table of modes: one row per mode and query set, numbered by mode as in the plot.
void AppendModeRows(const std::string& scene, const std::vector<Row>& rows, std::string& md, std::string& csv) {
  md += "| # | test | set | mode | queries | ns/test | FN | FP | of which in-plane |\n|---|---|---|---|---:|---:|---:|---:|---:|\n";
  std::vector<std::string> names;
  for (const Row& r : rows)
    if (std::find(names.begin(), names.end(), r.mode) == names.end()) names.push_back(r.mode);
  for (const Row& r : rows) {
    const std::size_t num = std::find(names.begin(), names.end(), r.mode) - names.begin() + 1;
    md += fmt::format("| {} | {} | {} | {} | {} | {:.1f} | {} | {} | {} |\n", num, r.test, r.set, r.mode, r.n, r.ns, r.fn, r.fp,
                      r.test == "ray-triangle" ? std::to_string(r.in_plane) : "-");
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
}

}  // namespace

ReportFiles OpenReportFiles(const std::string& dir, const Scene& scene) {
  ReportFiles f;
  f.base = (std::filesystem::path(dir) / (scene.name + "-accuracy")).string();
  f.md = OutputFile(f.base + ".md", {"the accuracy table", false, true, scene.files});
  f.csv = OutputFile(f.base + ".csv", {"the accuracy CSV", false, true, scene.files});
  f.png = OutputFile(f.base + ".png", {"the accuracy plot", false, true, scene.files});
  return f;
}

void WriteReport(ReportFiles& files, const Report& rep) {
  const Workload& w = *rep.workload;
  std::string md = fmt::format("### {} ({}x{}, crsh)\n\nQueries sampled uniformly from the frame's own work: {} cone-sphere tests of {} and {} ray-triangle tests of {}; near-boundary sets move each sphere to touch the bundle (radius within 2^-20 of the distance) and aim each ray at an edge (2^-22 of the edge across it). FN: the mode says miss where the exact answer is hit (a missed hit changes the image); FP: the reverse (an extra test costs time only); the plot draws them apart, FN filled and FP open. The CSV holds this table and the end-to-end ones (set `end-to-end`, columns frame_ms, tests, rays_changed). Time: median of three passes, one thread.\n\n",
                               rep.scene, rep.width, rep.height, w.cones.size(), w.cones_seen, w.tris.size(), w.tris_seen);
  // One header for both tables: a mode row fills the columns up to in_plane, an end-to-end row (set
  // "end-to-end") the last three.
  std::string csv = "scene,test,set,mode,queries,ns_per_test,false_negatives,false_positives,in_plane,frame_ms,tests,rays_changed\n";
  AppendModeRows(rep.scene, rep.rows, md, csv);
  AppendEndToEnd(rep, md, csv);
  files.md.Write(md);
  files.csv.Write(csv);
  Plot(files.png, fmt::format("{}: errors against time per test", rep.scene), rep.rows);
  PublishAll({&files.md, &files.csv, &files.png});
  std::printf("%s\n  wrote %s.md, .csv, .png\n", md.c_str(), files.base.c_str());
}

}  // namespace rayspace::app::accuracy
