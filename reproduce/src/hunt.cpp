// `reproduce hunt-mark`: its configurations, the paper's tables 1 and 5, and their sections.
#include "rayspace/reproduce/hunt.h"

#include <map>

#include <fmt/format.h>

#include "rayspace/reproduce/report.h"
#include "rayspace/reproduce/store.h"

namespace rayspace::reproduce {

const std::vector<HuntScene>& HuntScenes() {
  static const std::vector<HuntScene> scenes = {
      {"BUNNY-1K", "roger-bunny-res4.json", 1, "Bunny-1k", "bun_zipper_res4 (948 triangles) with Roger et al.'s ground and walls"},
      {"BUNNY-4K", "roger-bunny-res3.json", 1, "Bunny-4k", "bun_zipper_res3 (3,851 triangles), the same room"},
      {"BUNNY-16K", "roger-bunny-res2.json", 1, "Bunny-16k", "bun_zipper_res2 (16,301 triangles), the same room"},
      {"BUNNY-69K", "roger-bunny-full.json", 1, "Bunny-69k", "bun_zipper (69,451 triangles), the same room"},
      {"CONFERENCE", "conference.json", 1, "Conference", "331,179 triangles (the paper's version has 282k); our viewpoint"},
      {"SPONZA-SOFT", "sponza-soft.json", 5, "", "Sponza with a sphere light of radius 0.4 (the paper's Courtyard is not held)"},
      {"CONFERENCE-SOFT", "conference-soft.json", 5, "", "the conference room under a 60 x 60 rect light"},
  };
  return scenes;
}

std::vector<Config> HuntConfigs(int width, int height) {
  std::vector<Config> configs;
  for (const HuntScene& s : HuntScenes()) {
    Config c;
    c.target = "hunt-mark";
    c.scene = s.name;
    c.scene_file = s.file;
    c.algo = "grid";
    c.bounces = 0;  // eye rays and the shadow rays of their hits, as the paper's frames
    c.width = width;
    c.height = height;
    c.subdivision = c.levels = 0;
    if (s.table == 1) {
      c.primary = true;  // eye rays through the eye's grid
      configs.push_back(c);
      // The traversal's scaling with threads (the paper: "around 90% of linear with 8 cores"): the
      // largest bunny and the conference room again on one thread.
      if (s.name == "BUNNY-69K" || s.name == "CONFERENCE") {
        c.threads = 1;
        configs.push_back(c);
        c.threads = 0;
      }
      // Tables 2-4 set the grids beside a BVH and a software Z-buffer: the smallest bunny (standing in
      // for ERW6, 1K polygons) and the conference room again with Embree's BVH tracing the eye rays
      // and the hard shadows.
      if (s.name == "BUNNY-1K" || s.name == "CONFERENCE") {
        Config e = c;
        e.algo = "embree";
        configs.push_back(e);
      }
    } else {
      // The regular grid 54 along the longest side (rayspace's default), then sized to the
      // perspective grid's cells of one face (the fitted reading).
      for (const std::uint64_t regular_cells : {std::uint64_t{0}, kHuntEqualCells})
        for (const char* area : {"regular", "200x200x4"}) {
          c.grid_area = area;
          c.grid_regular_cells = regular_cells;
          configs.push_back(c);
        }
    }
  }
  return configs;
}

namespace {

struct Table1Row {
  std::string scene;
  std::uint64_t triangles;
  double primary_mrays, primary_build, shadow_mrays, shadow_build;  // build: share of the frame
  double soft_mrays, soft_build;                                     // soft shadows, 8 rays a pixel
};
// The paper's table 1, one 2.66 GHz Xeon core, 1920x1200.
const std::vector<Table1Row>& PaperTable1() {
  static const std::vector<Table1Row> rows = {
      {"Bunny-1k", 1000, 351, 0.01, 169, 0.10, 14.8, 0.0},   {"Bunny-4k", 4000, 274, 0.03, 141, 0.13, 13.3, 0.0},
      {"Bunny-16k", 16000, 185, 0.07, 109, 0.21, 11.7, 0.0}, {"Bunny-69k", 69000, 100, 0.18, 50, 0.27, 8.4, 0.01},
      {"Conference", 282000, 36, 0.33, 23, 0.45, 3.9, 0.01},
  };
  return rows;
}
constexpr double kPaperRegularSteps = 52.0, kPaperPerspectiveSteps = 12.7;  // table 5, Courtyard

const Result* FindScene(const std::vector<const Result*>& results, const std::string& scene, const std::string& area = "",
                        std::uint64_t regular_cells = 0, int threads = 0) {
  for (const Result* r : results)
    if (r->config.scene == scene && r->config.grid() && r->config.grid_area == area && r->config.grid_regular_cells == regular_cells &&
        r->config.threads == threads)
      return r;
  return nullptr;
}

// One ray type's block of the frame's grid statistics (render --stats: grids.per_type.<type>), and
// its area-light shadow rays' (area_light_rays); empty when absent.
nlohmann::json GridType(const Result& r, const char* type) {
  return r.statistics.value("grids", nlohmann::json::object()).value("per_type", nlohmann::json::object()).value(type, nlohmann::json::object());
}
nlohmann::json AreaRays(const Result& r) { return GridType(r, "shadow").value("area_light_rays", nlohmann::json::object()); }
// The scene's triangles: a ray type's brute force over its rays.
std::uint64_t Triangles(const Result& r) {
  for (const auto& [type, c] : r.counts.types)
    if (c.rays) return c.brute_force / c.rays;
  return 0;
}

void AddRelation(Table& t, std::vector<std::vector<std::string>>& rows, const std::string& relation, const std::string& where,
                 const Outcome& ours, const Outcome& published) {
  t.notes.push_back(fmt::format("- {}: {}: ours {} ({}); published {} ({})", where, relation, ours.holds ? "holds" : "fails", ours.detail,
                                published.holds ? "holds" : "fails", published.detail));
  rows.push_back({relation, where, ours.holds ? "holds" : "fails", ours.detail, published.holds ? "holds" : "fails", published.detail});
}

Outcome Fewer(double regular, double perspective) {
  return {perspective > 0 && perspective < regular,
          fmt::format("{:.1f} regular, {:.1f} perspective: x{:.2f}", regular, perspective, regular > 0 ? perspective / regular : 0.0)};
}

}  // namespace

namespace {

// The regular grid a run built: "90x41x43 (158,670 cells)".
std::string RegularGrid(const Result& r) {
  const nlohmann::json d = r.statistics.value("grids", nlohmann::json::object()).value("regular_dims", nlohmann::json::array());
  if (d.size() != 3) return "";
  const std::uint64_t x = d[0].get<std::uint64_t>(), y = d[1].get<std::uint64_t>(), z = d[2].get<std::uint64_t>();
  return fmt::format("{}x{}x{} ({} cells)", x, y, z, Thousands(x * y * z));
}

// Table 5 (cells per soft-shadow ray) and its relations (`verdicts`); the fitted reading's target
// into `fit`.
Table Table5(const std::vector<const Result*>& results, std::vector<std::vector<std::string>>& verdicts, Table& fit) {
  Table t5{"hunt-5", "Hunt and Mark table 5: grid cells visited per soft-shadow ray, regular grid against 3D perspective grid",
           {"scene", "series", "regular grid", "regular cells/ray", "perspective grid", "perspective cells/ray", "perspective / regular",
            "face cells/ray", "faces / regular", "regular tests/ray", "perspective tests/ray", "note"},
           {}, {}};
  const double paper = kPaperPerspectiveSteps / kPaperRegularSteps;
  t5.rows.push_back({"Courtyard", "published", "54x54x54 (157,464 cells)", fmt::format("{:.1f}", kPaperRegularSteps), "200x200x4",
                     fmt::format("{:.1f}", kPaperPerspectiveSteps), fmt::format("{:.2f}", paper), "", "", "", "",
                     "1920x1200, 8 soft-shadow rays per pixel"});
  const double lo = paper * (1 - kHuntRatioTolerance), hi = paper * (1 + kHuntRatioTolerance);
  const auto within = [&](double x) { return x >= lo && x <= hi ? "yes" : "no"; };
  for (const HuntScene& s : HuntScenes()) {
    if (s.table != 5) continue;
    for (const std::uint64_t cells : {std::uint64_t{0}, kHuntEqualCells}) {
      const Result* reg = FindScene(results, s.name, "regular", cells);
      const Result* per = FindScene(results, s.name, "200x200x4", cells);
      if (!reg || !per) continue;
      const nlohmann::json ra = AreaRays(*reg), pa = AreaRays(*per);
      const double a = ra.value("steps_per_ray", 0.0), b = pa.value("steps_per_ray", 0.0);
      // The perspective grid's own cells, without the core cube's regular cells (counted by the
      // emulator's walk; absent when the walks did not count them).
      const bool has_faces = pa.contains("face_steps_per_ray");
      const double f = pa.value("face_steps_per_ray", 0.0);
      const auto ratio = [&](double x) { return fmt::format("{:.2f}", a > 0 ? x / a : 0.0); };
      const std::string reading = cells ? fmt::format("about {} cells: ", Thousands(cells)) : "54 along the longest side: ";
      t5.rows.push_back({s.name, cells ? "ours, fitted" : "ours", reading + RegularGrid(*reg), fmt::format("{:.1f}", a), "200x200x4",
                         fmt::format("{:.1f}", b), ratio(b), has_faces ? fmt::format("{:.1f}", f) : "", has_faces ? ratio(f) : "",
                         fmt::format("{:.1f}", ra.value("tests_per_ray", 0.0)), fmt::format("{:.1f}", pa.value("tests_per_ray", 0.0)), s.note});
      AddRelation(t5, verdicts, kHuntFewerSteps, s.name + (cells ? " (regular grid of about equal cells)" : ""), Fewer(a, b),
                  Fewer(kPaperRegularSteps, kPaperPerspectiveSteps));
      if (cells && a > 0)
        fit.rows.push_back({s.name, RegularGrid(*reg), fmt::format("{:.2f}", b / a), within(b / a), has_faces ? ratio(f) : "",
                            has_faces ? within(f / a) : "not counted", fmt::format("{:.2f}", paper)});
    }
  }
  t5.notes.push_back(
      "Ours count every cell a ray visits: through the perspective grid, the regular grid's cells within the core cube about the "
      "light (8 times the light's reach, where rays from points off the centre would sweep many perspective columns) and then "
      "each face's cells; 'face cells/ray' leaves the core cube's cells out. Both grids test the triangles of each cell over the whole "
      "ray. Shadow rays of the eye rays' hits only (--bounces 0), 8 per point, at the run's frame size. The fitted rows size the "
      "regular grid by its cells (--grid-regular-cells), which also sizes the core cube's cells.");
  fit.notes.push_back(fmt::format(
      "The paper compares grids of essentially equal cell counts (54^3 = 157,464 regular cells against 200 x 200 x 4 = 160,000 of a "
      "face). The fitted reading gives our regular grid the count along the longest side whose cells are closest to {} (no "
      "published count is used to choose it). Target: perspective / regular within {:.0f} % of {:.2f}, that is {:.2f} to {:.2f}. The "
      "paper's perspective grid has no core cube: its cells are the faces' only, which the 'faces only' column compares.",
      Thousands(kHuntEqualCells), 100 * kHuntRatioTolerance, paper, lo, hi));
  return t5;
}

// Table 1 (rates and the build's share: times) and its trends.
Table Table1(const std::vector<const Result*>& results) {
  Table t1{"hunt-1", "Hunt and Mark table 1: eye rays, hard and soft shadows through perspective grids, rates and build share",
           {"scene", "series", "triangles", "eye Mrays/s", "eye build share", "shadow Mrays/s", "shadow build share", "soft Mrays/s",
            "soft build share", "eye tests/ray", "shadow tests/ray", "note"},
           {}, {}};
  for (const Table1Row& p : PaperTable1())
    t1.rows.push_back({p.scene, "published", Thousands(p.triangles), fmt::format("{:.1f}", p.primary_mrays), fmt::format("{:.0f}%", 100 * p.primary_build),
                       fmt::format("{:.1f}", p.shadow_mrays), fmt::format("{:.0f}%", 100 * p.shadow_build), fmt::format("{:.1f}", p.soft_mrays),
                       fmt::format("{:.0f}%", 100 * p.soft_build), "", "", "one 2.66 GHz core, 1920x1200"});
  // Each scene's hard-shadow rate and build share, for the soft shadows' relations.
  std::map<std::string, std::pair<double, double>> hard;
  std::vector<double> eye_rates, shadow_rates, eye_shares, shadow_shares;
  std::vector<std::string> bunnies;
  for (const HuntScene& s : HuntScenes()) {
    if (s.table != 1) continue;
    const Result* r = FindScene(results, s.name);
    if (!r) continue;
    // As the paper's columns: the eye's grid build against the eye rays' trace, the lights' grids
    // against the shadow rays'; each rate counts its own trace.
    const double eye_build = PassMs(*r, "grid.build.eye", true), light_build = PassMs(*r, "grid.build", true);
    const double eye = PassMs(*r, "grid.trace.primary"), shadow = PassMs(*r, "grid.trace.shadow");
    const double eye_rate = eye > 0 ? GridType(*r, "primary").value("rays", 0.0) / eye / 1e3 : 0.0, shadow_rate = shadow > 0 ? GridType(*r, "shadow").value("rays", 0.0) / shadow / 1e3 : 0.0;
    const auto share = [](double build, double trace) { return build + trace > 0 ? build / (build + trace) : 0.0; };
    const double eye_share = share(eye_build, eye), shadow_share = share(light_build, shadow);
    t1.rows.push_back({s.name, "ours", Thousands(Triangles(*r)), fmt::format("{:.2f}", eye_rate), fmt::format("{:.0f}%", 100 * eye_share),
                       fmt::format("{:.2f}", shadow_rate), fmt::format("{:.0f}%", 100 * shadow_share), "", "",
                       fmt::format("{:.1f}", GridType(*r, "primary").value("tests_per_ray", 0.0)),
                       fmt::format("{:.1f}", GridType(*r, "shadow").value("tests_per_ray", 0.0)), s.note});
    hard[s.name] = {shadow_rate, shadow_share};
    // Table 1's text: "hard shadow rays are not quite as fast as eye rays by the metric of ray-segments / sec".
    for (const Table1Row& p : PaperTable1()) {
      if (p.scene != s.paper) continue;
      const auto slower = [](double eye, double shadow) {
        return Outcome{shadow < eye, fmt::format("eye {:.2f}, hard shadows {:.2f} Mrays/s", eye, shadow)};
      };
      std::vector<std::vector<std::string>> unused;
      AddRelation(t1, unused, kHuntHardSlower, s.name, slower(eye_rate, shadow_rate), slower(p.primary_mrays, p.shadow_mrays));
    }
    if (s.name.rfind("BUNNY", 0) == 0) {
      eye_rates.push_back(eye_rate), shadow_rates.push_back(shadow_rate), bunnies.push_back(s.name);
      eye_shares.push_back(eye_share), shadow_shares.push_back(shadow_share);
    }
  }
  // Soft shadows (the paper's third column group): the soft-shadow scenes' 200x200x4 frames, eye rays
  // rasterised, 8 area-light shadow rays per point; the build is every grid's (the lights' 3D grids
  // and the regular grid) against the shadow rays' trace.
  for (const HuntScene& s : HuntScenes()) {
    if (s.table != 5) continue;
    const Result* r = FindScene(results, s.name, "200x200x4");
    if (!r) continue;
    const double build = PassMs(*r, "grid.build", true), shadow = PassMs(*r, "grid.trace.shadow");
    const double rate = shadow > 0 ? GridType(*r, "shadow").value("rays", 0.0) / shadow / 1e3 : 0.0;
    const double share = build + shadow > 0 ? build / (build + shadow) : 0.0;
    t1.rows.push_back({s.name, "ours", Thousands(Triangles(*r)), "", "", "", "", fmt::format("{:.2f}", rate), fmt::format("{:.0f}%", 100 * share), "",
                       fmt::format("{:.1f}", GridType(*r, "shadow").value("tests_per_ray", 0.0)), s.note});
    // The conference room under its rect light against its hard shadows (the paper's Conference row).
    const auto it = hard.find("CONFERENCE");
    if (s.name != "CONFERENCE-SOFT" || it == hard.end()) continue;
    const Table1Row& p = PaperTable1().back();
    std::vector<std::vector<std::string>> unused;
    const auto slower = [](double hard_rate, double soft_rate) {
      return Outcome{soft_rate < hard_rate / 2, fmt::format("hard {:.2f}, soft {:.2f} Mrays/s", hard_rate, soft_rate)};
    };
    AddRelation(t1, unused, kHuntSoftSlower, "CONFERENCE", slower(it->second.first, rate), slower(p.shadow_mrays, p.soft_mrays));
    const auto smaller = [](double hard_share, double soft_share) {
      return Outcome{soft_share < hard_share, fmt::format("hard {:.0f}%, soft {:.0f}%", 100 * hard_share, 100 * soft_share)};
    };
    AddRelation(t1, unused, kHuntSoftBuild, "CONFERENCE", smaller(it->second.second, share), smaller(p.shadow_build, p.soft_build));
  }
  t1.plot_x = "triangles";
  t1.plot_y = "eye Mrays/s";
  t1.plot_group = "series";
  t1.notes.push_back(
      "Ours: the emulated grid.trace (render's path: eye rays per cell and triangle in SIMD lanes, Hunt and Mark's tiled "
      "order; shadow rays' cell triangles in lanes) on this machine's threads at the run's frame size, one eye ray and one "
      "hard-shadow ray per pixel, 200 cells a face for the light, about 100x100-pixel cells for the eye; the builds (in "
      "double, on the host) timed grid by grid: the eye's build share is of the eye's grid build and the eye rays' trace, "
      "the shadow share of the light's grid build and the shadow rays' trace, as the paper's columns. The paper's rates are a 2008 "
      "core's on 1920x1200 frames; only the trends compare. Times vary run to run. A point light's grid has six faces of "
      "200 x 200 cells (the paper's one face of a light at the scene's side): the build is a larger share of our frames "
      "than of the paper's.");
  if (eye_rates.size() >= 2) {
    // Each relation compares like with like: eye rays' rate with the paper's eye rays', shadows' with
    // shadows'; the eye's build share with the paper's eye column, the lights' with its shadow column.
    const auto& p = PaperTable1();
    const auto falls = [](double from, double to) { return Outcome{to < from, fmt::format("{:.2f} to {:.2f} Mrays/s", from, to)}; };
    const auto rises = [](double from, double to) { return Outcome{to > from, fmt::format("{:.0f}% to {:.0f}%", 100 * from, 100 * to)}; };
    std::vector<std::vector<std::string>> unused;
    const std::string where = bunnies.front() + " to " + bunnies.back();
    AddRelation(t1, unused, kHuntRaysFall + std::string(" (eye rays)"), where, falls(eye_rates.front(), eye_rates.back()),
                falls(p[0].primary_mrays, p[3].primary_mrays));
    AddRelation(t1, unused, kHuntRaysFall + std::string(" (hard shadows)"), where, falls(shadow_rates.front(), shadow_rates.back()),
                falls(p[0].shadow_mrays, p[3].shadow_mrays));
    AddRelation(t1, unused, kHuntBuildRises + std::string(" (the eye's grid)"), where, rises(eye_shares.front(), eye_shares.back()),
                rises(p[0].primary_build, p[3].primary_build));
    AddRelation(t1, unused, kHuntBuildRises + std::string(" (the light's grid)"), where, rises(shadow_shares.front(), shadow_shares.back()),
                rises(p[0].shadow_build, p[3].shadow_build));
  }
  return t1;
}

}  // namespace

namespace {

// The paper's tables 2-4 (frames per second at 1024x1024 on one 2.66 GHz core; the others adjusted to it).
struct Table234Row {
  const char* table;
  const char* scene;     // ours
  const char* paper;     // the paper's scene
  const char* relation;
  double us, them;       // the paper's: ours and the compared system's (fps, or Mtri/s for table 4)
};
const std::vector<Table234Row>& PaperTables234() {
  static const std::vector<Table234Row> rows = {
      {"2", "BUNNY-1K", "ERW6 (1K polygons)", kHuntFasterEye, 106, 64},
      {"2", "CONFERENCE", "Conf (282K)", kHuntFasterEye, 22, 16},
      {"2", "BUNNY-1K", "ERW6 (1K polygons)", kHuntFasterShadow, 36, 23},
      {"2", "CONFERENCE", "Conf (282K)", kHuntFasterShadow, 6.8, 7.2},
      {"3", "BUNNY-1K", "ERW6 (1K polygons)", kHuntFasterStatic, 106, 49},
      {"3", "CONFERENCE", "Conf (282K)", kHuntFasterStatic, 22, 14},
      {"4", "BUNNY-69K", "Bunny (69.5K), Pixomatic", kHuntZBuffer, 8.32, 7.92},
  };
  return rows;
}

// The times each comparison sets side by side (ms of this run): ours (the grids) and the compared.
struct Compared {
  double ours = 0, them = 0;
  bool ok = false;
};
Compared Times(const Table234Row& row, const Result& grid, const Result* bvh) {
  const double eye_build = PassMs(grid, "grid.build.eye", true), light_build = PassMs(grid, "grid.build", true);
  const double eye = PassMs(grid, "grid.trace.primary"), shadow = PassMs(grid, "grid.trace.shadow");
  if (row.relation == kHuntZBuffer) {
    // Triangles per ms: the eye rays' grid (build and trace) against the frame's raster pass.
    const double tris = static_cast<double>(Triangles(grid)), raster = PassMs(grid, "raster", true);
    return {tris / (eye_build + eye), tris / raster, eye_build + eye > 0 && raster > 0};
  }
  if (!bvh) return {};
  // The BVH is built inside its first batch (the eye rays'): its trace is the pass less the build.
  const double bvh_build = PassMs(*bvh, "embree.build", true);
  const double bvh_eye = PassMs(*bvh, "trace.primary") - bvh_build, bvh_shadow = PassMs(*bvh, "trace.shadow");
  if (row.relation == kHuntFasterEye) return {eye_build + eye, bvh_build + bvh_eye, bvh_build > 0};
  if (row.relation == kHuntFasterShadow) return {eye_build + eye + light_build + shadow, bvh_build + bvh_eye + bvh_shadow, bvh_build > 0};
  return {eye_build + eye, bvh_eye, bvh_eye > 0};
}

}  // namespace

// Tables 2-4: the grids against Embree's BVH and the emulated raster, as the relations they support.
Table Tables234(const std::vector<const Result*>& results) {
  Table t{"hunt-2-4", "Hunt and Mark tables 2-4: the perspective grids against a BVH and a software Z-buffer (ours: this run, this machine)",
          {"table", "scene", "paper's scene", "relation", "ours: grids", "ours: compared", "ours: speed-up", "ours", "published: speed-up",
           "published"},
          {}, {}};
  for (const Table234Row& row : PaperTables234()) {
    const Result* grid = FindScene(results, row.scene);
    const Result* bvh = nullptr;
    for (const Result* r : results)
      if (r->config.scene == row.scene && r->config.embree()) bvh = r;
    if (!grid || !grid->config.primary) continue;
    const Compared c = Times(row, *grid, bvh);
    if (!c.ok) continue;
    const bool rate = row.relation == kHuntZBuffer;
    // Times: the speed-up is theirs over ours; rates (table 4): ours over theirs.
    const double speedup = rate ? c.ours / c.them : c.them / c.ours, published = row.us / row.them;
    const auto holds = [&](double s) { return rate ? s >= 0.5 && s <= 2.0 : s > 1.0; };
    t.rows.push_back({row.table, row.scene, row.paper, row.relation,
                      rate ? fmt::format("{:.2f} Mtri/s", c.ours / 1e3) : fmt::format("{:.1f} ms", c.ours),
                      rate ? fmt::format("{:.2f} Mtri/s", c.them / 1e3) : fmt::format("{:.1f} ms", c.them), fmt::format("x{:.2f}", speedup),
                      holds(speedup) ? "holds" : "fails", fmt::format("x{:.2f} ({} against {})", published, row.us, row.them),
                      holds(published) ? "holds" : "fails"});
  }
  if (t.rows.empty()) return t;
  t.notes.push_back(
      "Ours: the grid configuration's frame (eye rays through the eye's perspective grid, one hard-shadow ray per pixel through "
      "the light's) against the same scene traced by Embree 3 (`--algo embree --primary embree`, the eye rays and the hard "
      "shadows), at the run's size on this machine's threads. Table 2's BVH is rebuilt each frame (Embree's build, timed as the "
      "sub-pass embree.build, counted); table 3's is static (its build left out). Table 4 sets the eye rays' grid (build and "
      "trace) against the frame's emulated raster pass, both in triangles per millisecond of the scene's triangles, where the "
      "paper's Pixomatic rate covered 5 % of the window: our view covers more. The paper's frames per second are at 1024x1024 "
      "on one 2008 core, the other systems' adjusted to it; ERW6 and Fairy are not held: BUNNY-1K (948 triangles in a room) "
      "stands in for ERW6, Fairy has none. Times vary run to run.");
  return t;
}

// The traversal's scaling: each scene's grid.trace on one thread against the run's threads.
constexpr double kPaperScaling = 0.9, kScalingWell = 0.8;
Table ScalingTable(const std::vector<const Result*>& results) {
  Table t{"hunt-scaling", "Hunt and Mark section 6: the traversal's scaling with threads (ours: this run, this machine)",
          {"scene", "threads", "grid.trace ms, 1 thread", "grid.trace ms", "speed-up", "of linear", "relation", "ours", "published"},
          {}, {}};
  for (const HuntScene& s : HuntScenes()) {
    const Result* one = FindScene(results, s.name, "", 0, 1);
    const Result* many = FindScene(results, s.name);
    if (!one || !many) continue;
    const int n = many->timings.value("threads", 0);
    const double t1 = PassMs(*one, "grid.trace"), tn = PassMs(*many, "grid.trace");
    const double speedup = tn > 0 ? t1 / tn : 0.0, of_linear = n > 0 ? speedup / n : 0.0;
    t.rows.push_back({s.name, std::to_string(n), fmt::format("{:.1f}", t1), fmt::format("{:.1f}", tn), fmt::format("x{:.2f}", speedup),
                      fmt::format("{:.0f}%", 100 * of_linear), "the traversal scales at least 80 % of linear",
                      n > 1 && of_linear >= kScalingWell ? "holds" : "fails", fmt::format("holds (about {:.0f}% with 8 cores)", 100 * kPaperScaling)});
  }
  t.notes.push_back(
      "The paper (section 6): \"We have already parallelized the traversal algorithm, and as expected we observe good scaling "
      "(around 90% of linear with 8 cores)\"; its build was not parallel. Ours: the eye and shadow rays' grid.trace passes "
      "(the build excluded, as the paper's claim), one thread against the run's (cores / --jobs); the 80 % bound is the "
      "project's reading of \"good scaling\". A machine shared with other work lowers the speed-up.");
  return t;
}

void AddHuntReport(Report& report, Report& timings, const std::vector<const Result*>& results) {
  if (results.empty()) return;
  std::vector<std::vector<std::string>> verdicts;
  Table fit{"hunt-fit", "Hunt and Mark's grid sizes, fitted: table 5's ratio with grids of about equal cells",
            {"scene", "regular grid", "perspective / regular", "within 25 %", "faces only / regular", "within 25 % (faces only)", "published"},
            {}, {}};
  Table t5 = Table5(results, verdicts, fit), t1 = Table1(results);
  if (!verdicts.empty()) {  // some soft-shadow scene measured both ways
    Table summary{"hunt-summary", "Hunt and Mark 2008: its tables' relations on our counts",
                  {"relation", "where", "ours", "compared", "published", "published compared"}, verdicts, {}};
    summary.notes.push_back("Table 1's rates are times: they and their relations are in timings.md.");
    report.tables.push_back(std::move(summary));
    if (!fit.rows.empty()) report.tables.push_back(std::move(fit));
    report.tables.push_back(std::move(t5));
  }
  if (t1.rows.size() > PaperTable1().size()) timings.tables.push_back(std::move(t1));  // some of ours beside the published
  if (Table scaling = ScalingTable(results); !scaling.rows.empty()) timings.tables.push_back(std::move(scaling));
  if (Table t234 = Tables234(results); !t234.rows.empty()) timings.tables.push_back(std::move(t234));
}

}  // namespace rayspace::reproduce
