// `rayspace reproduce`'s logic on hand-made numbers: the relations' verdicts, the published tables'
// parsing, the shards' coverage check and the summary's counts.
#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <iterator>

#include "rayspace/error.h"
#include "rayspace/reproduce/faithful_table.h"
#include "rayspace/reproduce/fit_report.h"
#include "rayspace/reproduce/hunt.h"
#include "rayspace/reproduce/relations.h"
#include "rayspace/reproduce/runner.h"
#include "rayspace/reproduce/report.h"
#include "rayspace/reproduce/roger.h"
#include "rayspace/reproduce/store.h"
#include "rayspace/reproduce/toczek.h"

namespace rayspace::reproduce {
namespace {

// A two-level hierarchy of one ray type: level 2 then level 1 (intersections, hits).
Measurement Hand(std::uint64_t total, std::uint64_t brute, LevelCounts top, LevelCounts bottom) {
  Measurement m;
  m.total = total;
  m.brute_force = brute;
  m.levels["SH"] = {bottom, top};
  m.top_nodes_x_triangles["SH"] = top.intersections;
  return m;
}

TEST_CASE("reproduce: relations hold or fail on hand-made numbers") {
  // 100 + 40 + level-1 hits 5 x subdivision 8 = 180.
  const Measurement rah = Hand(180, 1000, {100, 10}, {40, 5});
  const Measurement crsh = Hand(150, 1000, {60, 10}, {50, 5});
  CHECK(CrshBelowRah(rah, crsh).holds);
  CHECK(Verdict(CrshBelowRah(rah, crsh)) == "holds");
  const Outcome reversed = CrshBelowRah(crsh, rah);
  CHECK_FALSE(reversed.holds);
  CHECK(Verdict(reversed) == "fails");
  CHECK(reversed.detail == "180 >= 150");
  CHECK(Verdict(std::nullopt) == "n/a");

  CHECK(Identity(rah, 8).holds);
  const Outcome off = Identity(rah, 16);  // 100 + 40 + 5 x 16 = 220
  CHECK_FALSE(off.holds);
  CHECK(off.detail == "180 != 220");

  CHECK(Below(crsh, rah).holds);
  CHECK_FALSE(Below(rah, crsh).holds);
  CHECK(Above(rah, crsh).holds);
  CHECK(Above(rah, crsh).detail == "180 > 150");
  CHECK_FALSE(Above(rah, rah).holds);  // equal is neither above nor below
  CHECK(Above(rah, rah).detail == "180 <= 180");
  CHECK_FALSE(Below(rah, rah).holds);
  CHECK(BelowBrute(rah).holds);
  CHECK_FALSE(BelowBrute(Hand(1000, 1000, {1, 0}, {1, 0})).holds);

  CHECK(RahTopLevel(rah, 2).holds);
  Measurement culled = rah;
  culled.top_nodes_x_triangles["SH"] = 120;
  CHECK_FALSE(RahTopLevel(culled, 2).holds);
  CHECK(Thousands(1234567) == "1,234,567");
  CHECK(Thousands(12) == "12");
}

TEST_CASE("reproduce roger: relations hold on good counts and fail on bad ones") {
  // Growth: in x order, whatever order the points come in; a flat or falling step fails.
  const Outcome up = GrowsWith({{16, 3000}, {4, 1000}, {8, 2000}});
  CHECK(up.holds);
  CHECK(up.detail == "1,000 < 2,000 < 3,000");
  const Outcome flat = GrowsWith({{4, 1000}, {8, 1000}, {16, 3000}});
  CHECK_FALSE(flat.holds);
  CHECK(flat.detail == "1,000 >= 1,000 < 3,000");
  CHECK_FALSE(GrowsWith({{16, 500}, {4, 1000}}).holds);
  CHECK_FALSE(GrowsWith({{4, 1000}}).holds);  // one point shows no growth

  CHECK(InRange(3.2, 2.5, 4.5).holds);
  CHECK(InRange(2.5, 2.5, 4.5).holds);
  const Outcome many = InRange(12.25, 2.5, 4.5);
  CHECK_FALSE(many.holds);
  CHECK(many.detail == "12.25 not in [2.5, 4.5]");

  CHECK(SubLinear(1000, 2100, 4.0).holds);
  const Outcome linear = SubLinear(1000, 4000, 4.0);
  CHECK_FALSE(linear.holds);
  CHECK(linear.detail == "x4.00 >= x4 pixels (1,000 -> 4,000)");
  CHECK_FALSE(SubLinear(0, 10, 4.0).holds);
  // Figure 10: the irregular reflector's work grows faster with the room than the smooth one's.
  const Outcome faster = GrowsFaster(3.68, 2.97);
  CHECK(faster.holds);
  CHECK(faster.detail == "x3.68 > x2.97");
  CHECK_FALSE(GrowsFaster(2.97, 2.97).holds);
  CHECK(GrowsFaster(1.5, 2.0).detail == "x1.50 <= x2.00");
  // Figure 12: the loose frame's work is no more than the tight one's (equal holds).
  CHECK(NotAbove(657.2, 657.2).holds);
  const Outcome above = NotAbove(671.9, 657.2);
  CHECK_FALSE(above.holds);
  CHECK(above.detail == "671.90 > 657.20");
  // Museum8: shadows more than double the time; the published ratio 3330 / 1316 rides along.
  const Outcome doubled = MoreThanDouble(2.31, 1.0);
  CHECK(doubled.holds);
  CHECK(doubled.detail == "x2.31 > x2 (published x2.53)");
  CHECK_FALSE(MoreThanDouble(2.0, 1.0).holds);
  CHECK_FALSE(MoreThanDouble(5.0, 0.0).holds);
  // Figure 14(c): faster than the BVH's frame; equal or no BVH frame is not faster.
  const Outcome half = FasterThanBvh(50.0, 100.0);
  CHECK(half.holds);
  CHECK(half.detail == "x0.50 the BVH's frame (published about x0.5)");
  CHECK_FALSE(FasterThanBvh(100.0, 100.0).holds);
  CHECK_FALSE(FasterThanBvh(100.0, 0.0).holds);
  // Figure 14(b): the ratio to the BVH crosses 1 from the fewest polygons to the most, in polygon order.
  const Outcome crosses = OvertakesBvh({{69451, 0.8}, {948, 1.4}, {3851, 1.1}});
  CHECK(crosses.holds);
  CHECK(crosses.detail == "x1.40, x1.10, x0.80 from the fewest polygons to the most");
  CHECK_FALSE(OvertakesBvh({{948, 4.5}, {3851, 11.7}}).holds);   // slower and slower
  CHECK_FALSE(OvertakesBvh({{948, 0.5}, {3851, 0.4}}).holds);    // faster throughout: never slower
  CHECK_FALSE(OvertakesBvh({{948, 1.5}}).holds);                 // one point compares nothing
}

TEST_CASE("reproduce roger: the report's verdicts follow the counts") {
  // Two levels of detail and two sizes of a frame with one ray type: cone-sphere tests are the sum
  // of the levels' intersections.
  auto result = [](const std::string& scene, int side, std::uint64_t cone, std::uint64_t final_tests, std::uint64_t rays) {
    Result r;
    r.config.target = "roger";
    r.config.scene = scene;
    r.config.algo = "rah-quadtree";
    r.config.width = r.config.height = side;
    TypeCounts& t = r.counts.types["reflection"];
    t.levels = {{cone / 2, 1}, {cone - cone / 2, 1}};
    t.final_tests = final_tests;
    t.rays = rays;
    t.brute_force = rays * 100;
    r.counts.total = cone + final_tests;
    return r;
  };
  auto verdicts = [](const std::vector<Result>& rs) {
    std::vector<const Result*> ptrs;
    for (const Result& r : rs) ptrs.push_back(&r);
    Report report;
    AddRogerReport(report, ptrs);
    const auto summary = std::find_if(report.tables.begin(), report.tables.end(), [](const Table& t) { return t.id == "roger-summary"; });
    REQUIRE(summary != report.tables.end());
    std::map<std::string, std::string> by_claim;
    for (const auto& row : summary->rows) by_claim[row[0] + " | " + row[1]] = row[2];
    return by_claim;
  };
  const std::string lod = std::string(kRogerGrowsLod) + " | rah-quadtree, cone-sphere tests";
  const std::string pixels = std::string(kRogerSubLinear) + " | rah-quadtree, 32x32 -> 64x64";
  const std::string per_ray = std::string(kRogerPerRay) + " | rah-quadtree, BUNNY res4, 64x64";
  const std::vector<Result> good = {result("BUNNY res4", 64, 1000, 300, 100), result("BUNNY res3", 64, 1500, 300, 100),
                                    result("BUNNY res4", 32, 600, 80, 25)};
  auto v = verdicts(good);
  CHECK(v.at(lod) == "holds");
  CHECK(v.at(pixels) == "holds");  // 600 -> 1000: x1.67
  CHECK(v.at(per_ray) == "holds");  // 3 per ray
  const std::vector<Result> bad = {result("BUNNY res4", 64, 2400, 900, 100), result("BUNNY res3", 64, 1500, 300, 100),
                                   result("BUNNY res4", 32, 600, 80, 25)};
  v = verdicts(bad);
  CHECK(v.at(lod) == "fails");     // the finer bunny took fewer tests
  CHECK(v.at(pixels) == "fails");  // 600 -> 2400: x4
  CHECK(v.at(per_ray) == "fails");  // 9 per ray
}

TEST_CASE("reproduce roger: the report's rows do not depend on the results' order, configurations that differ by a switch included") {
  // The quadtree with and without --leaf-test differ only in their switches: the table order must
  // tell them apart, or the rows of a tie follow the order the results came in.
  auto result = [](const std::string& scene, bool leaf_test, std::uint64_t cone) {
    Result r;
    r.config.target = "roger";
    r.config.scene = scene;
    r.config.algo = "rah-quadtree";
    r.config.width = r.config.height = 64;
    if (leaf_test) r.config.switches = {"--leaf-test", "ray-sphere"};
    TypeCounts& t = r.counts.types["reflection"];
    t.levels = {{cone / 2, 1}, {cone - cone / 2, 1}};
    t.final_tests = cone / 3;
    t.rays = 100;
    t.brute_force = 100 * 100;
    r.counts.total = cone + t.final_tests;
    r.timings = {{"frame_ms", 1.0}, {"phases", nlohmann::json::array()}};
    return r;
  };
  std::vector<Result> forward;
  for (const char* scene : {"BUNNY res4", "BUNNY res3", "WAVY n=4", "WAVY n=8"})
    for (const bool leaf : {false, true}) forward.push_back(result(scene, leaf, leaf ? 900 : 1200));
  const std::vector<Result> backward(forward.rbegin(), forward.rend());
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rayspace-roger-order";
  auto report = [&](const std::vector<Result>& results) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    WriteReport(dir, results);
    std::ifstream in(dir / "report.md");
    return std::string{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  };
  const std::string a = report(forward), b = report(backward);
  std::filesystem::remove_all(dir);
  CHECK(a.find("rah-quadtree --leaf-test ray-sphere, BUNNY res4, 64x64") != std::string::npos);
  CHECK(a == b);
}

TEST_CASE("reproduce: the summary counts each relation's verdicts, the paper's apart from the project's") {
  const std::vector<RelationRow> rows = {
      {kCrshBelowRah, "a", Outcome{true, ""}, Outcome{true, ""}, "sec. 4.4"},
      {kCrshBelowRah, "b", Outcome{false, ""}, Outcome{true, ""}, "sec. 4.4"},
      {kIdentity, "a", std::nullopt, Outcome{false, ""}, ""},
  };
  const Table t = SummaryTable(rows);
  REQUIRE(t.rows.size() == 1);
  CHECK(t.rows[0] == std::vector<std::string>{kCrshBelowRah, "sec. 4.4", "1 of 2", "2 of 2"});
  const Table project = SummaryTable(rows, false);
  REQUIRE(project.rows.size() == 1);
  CHECK(project.rows[0][0] == kIdentity);
  CHECK(project.rows[0][1].find("35 of the 36") != std::string::npos);  // why the project checks it
  CHECK(project.rows[0][2] == "n/a");  // nothing judged: n/a, not "0 of 0"
  CHECK(project.rows[0][3] == "0 of 1");
  CHECK(project.title.find("not stated by the papers") != std::string::npos);
}

TEST_CASE("reproduce: slot accounting turns the pairs tested into the thesis's counts (SPONZA RAH s16 d4, table 4.23)") {
  // The thesis's 256,713 rays at subdivision 16: 16,045 level-1 nodes, 1,003 at level 2, 63 at level 3
  // under 4 top nodes. What a frame tests: the top level every (top node, triangle) pair; level 3 the
  // 63 nodes' pairs under hit parents; the levels below from the published hits.
  Counts c;
  TypeCounts& t = c.types["shadow"];
  t.levels = {{0, 10038322}, {4186350 * 16, 34655887}, {63 * 66450, 4186350}, {265800, 265800}};
  t.levels[0].intersections = 34655887 * 16;
  t.final_tests = 10038322 * 16;
  t.total = t.final_tests + t.levels[0].intersections + t.levels[1].intersections + t.levels[2].intersections + t.levels[3].intersections;
  c.total = t.total;
  const Counts slots = SlotAccounting(c, 16);
  const TypeCounts& s = slots.types.at("shadow");
  CHECK(s.levels[2].intersections == 4252800);  // 64 slots x 66,450: the thesis's level 3
  CHECK(s.levels[2].misses() == 66450);         // the empty slot's tests, all misses
  CHECK(s.levels[3].intersections == 265800);   // the top level as tested
  CHECK(slots.total == 786607544);              // the thesis's total, table 4.24
  CHECK(c.total == 786607544 - 66450);          // the pairs tested: one slot fewer
  Counts quadtree;  // no levels: kept as it is
  quadtree.types["shadow"].total = quadtree.total = 7;
  CHECK(SlotAccounting(quadtree, 4).total == 7);
}

TEST_CASE("reproduce: the published CSV files parse, and a bad row is named") {
  const std::string levels = "subdivision,depth,scene,algorithm,ray_type,level,metric,count\n8,2,OFFICE,RAH,SH,2,intersections,42\n";
  const std::string totals = "subdivision,depth,scene,algorithm,total_intersections,relative_percent\n8,2,OFFICE,RAH,100,5.5\n";
  const std::string timings = "scene,algorithm,ms_per_frame,phase,total_ms_58_frames,relative_percent\nOFFICE,RAH,618,ray_creation,40.2,0.11\n";
  const Published p = ParsePublished(levels, totals, timings, "x/");
  REQUIRE(p.Level({8, 2}, "OFFICE", "RAH", "SH", 2, "intersections"));
  CHECK(*p.Level({8, 2}, "OFFICE", "RAH", "SH", 2, "intersections") == 42);
  CHECK(p.Level({8, 3}, "OFFICE", "RAH", "SH", 2, "intersections") == nullptr);
  CHECK(p.Total({8, 2}, "OFFICE", "RAH")->second == doctest::Approx(5.5));
  CHECK(p.timings.at(0).phase == "ray_creation");
  CHECK_THROWS_WITH_AS(ParsePublished(levels + "8,2,OFFICE\n", totals, timings, "x/"), "x/crsh_levels.csv:3: 3 columns, expected 8",
                       InputError);
  CHECK_THROWS_WITH_AS(ParsePublished(levels, "h\n8,2,OFFICE,RAH,lots,5.5\n", timings, "x/"),
                       "x/crsh_totals.csv: row 2: total_intersections 'lots' is not a number", InputError);
}

TEST_CASE("reproduce: the embedded thesis tables hold the one published inconsistency") {
  const Published& p = ThesisPublished();
  CHECK(p.totals.size() == 54);
  const auto sponza_d3 = PublishedMeasurement(p, {8, 3}, "SPONZA", "RAH");
  REQUIRE(sponza_d3);
  CHECK(sponza_d3->total == 632408864);
  const Outcome o = Identity(*sponza_d3, 8);
  CHECK_FALSE(o.holds);
  CHECK(o.detail == "632,408,864 != 610,873,884");
  const auto sponza_d2 = PublishedMeasurement(p, {8, 2}, "SPONZA", "RAH");
  CHECK(Identity(*sponza_d2, 8).holds);
  CHECK(RahTopLevel(*sponza_d2, 2).holds);
  // The report's own line for it: the arithmetic, and the row it was copied from.
  const Table t = MisprintsTable(p);
  REQUIRE(t.rows.size() == 1);
  CHECK(t.rows[0][0] == "4.8");
  CHECK(t.rows[0][1] == "SPONZA RAH s8 d3");
  CHECK(t.rows[0][2] == "632,408,864");
  CHECK(t.rows[0][4] == "610,873,884");
  CHECK(t.rows[0][5] == "+21,534,980");
  CHECK(t.rows[0][6] == "SPONZA RAH s8 d2");
}

// A result of `algo` on SPONZA at subdivision 8, depth 2, 512x512, with a total.
// It traces the thesis's 256,713 shadow rays, so that tests per ray compare as totals would.
Result SponzaTotal(const std::string& algo, const std::string& faithful, double total) {
  Result r;
  r.config.scene = "SPONZA";
  r.config.algo = algo;
  r.config.faithful = faithful;
  r.counts.total = static_cast<std::uint64_t>(total);
  r.counts.types["shadow"].rays = 256713;
  return r;
}

TEST_CASE("reproduce: the faithful table judges each total per ray and the CRSH/RAH ratio against 15 %") {
  // Published, table 4.4: SPONZA s8 d2 RAH 632,408,864 and CRSH 405,619,896 (ratio 0.6414).
  const std::vector<Result> results = {SponzaTotal("rah", "thesis", 632408864 * 1.10), SponzaTotal("crsh", "thesis", 405619896 * 0.80),
                                       SponzaTotal("rah", "", 1e9), SponzaTotal("crsh", "", 1e8)};
  std::vector<RelationRow> relations;
  const Table t = FaithfulTable(results, ThesisPublished(), relations);
  REQUIRE(t.rows.size() == 1);
  const std::vector<std::string>& row = t.rows[0];
  CHECK(row[0] == "SPONZA");
  CHECK(row[4] == "1.100");
  CHECK(row[7] == "0.800");
  CHECK(row[9] == "0.100");   // defaults: 1e8 / 1e9
  CHECK(row[10] == "0.466");  // faithful: 0.8 x 405,619,896 / (1.1 x 632,408,864)
  CHECK(row[11] == "1 of 3 within 15 %");
  REQUIRE(relations.size() == 3);
  CHECK(relations[0].relation == std::string(kFaithfulTotal));
  CHECK(relations[0].where == "SPONZA s8 d2 RAH");
  CHECK(relations[0].ours->holds);
  CHECK_FALSE(relations[1].ours->holds);
  CHECK(relations[1].ours->detail == "1264.0 vs 1580.1: -20.0 %");
  // Twice the thesis's rays and twice its total is the same number per ray: within the tolerance.
  Result doubled = SponzaTotal("rah", "thesis", 2.0 * 632408864);
  doubled.counts.types["shadow"].rays = 2 * 256713;
  std::vector<RelationRow> per_ray;
  FaithfulTable({doubled}, ThesisPublished(), per_ray);
  REQUIRE_FALSE(per_ray.empty());
  CHECK(per_ray[0].ours->holds);
  CHECK_FALSE(relations[2].ours->holds);
  CHECK_FALSE(relations[2].published.has_value());
  // Just inside the tolerance holds (1.15 x the published, rounded down); just past it fails.
  relations.clear();
  FaithfulTable({SponzaTotal("rah", "thesis", 632408864 * 1.15), SponzaTotal("crsh", "thesis", 405619896 * 1.151)}, ThesisPublished(),
                relations);
  CHECK(relations[0].ours->holds);
  CHECK_FALSE(relations[1].ours->holds);
}

TEST_CASE("reproduce: the canonical text names every setting, and keeps the defaults' keys") {
  Config c;
  c.scene = "SPONZA";
  c.scene_file = "sponza-thesis.json";
  c.algo = "crsh";
  // The text the default configurations' results were stored under before the faithful settings
  // existed: they must still be found (--resume, merge).
  CHECK(c.Canonical() ==
        "target=thesis scene=SPONZA file=sponza-thesis.json algo=crsh subdivision=8 levels=2 bounces=1 size=512x512 "
        "objects=flat backend=emu");
  c.faithful = "thesis";
  c.one_object = true;
  // A preset is keyed by the switches it stands for, so a preset that changes names new results.
  CHECK(c.Canonical().ends_with(
      " faithful=thesis [--shadow-bounces first --objects flat --child-merge pairwise] "
      "one-object"));
  Config merged_only = c;
  merged_only.faithful.clear();
  CHECK(merged_only.Canonical().ends_with("backend=emu one-object"));
  // The ablation's switches name their results and survive the result file (a result read back
  // without them would be scored as the defaults').
  Config ablation = merged_only;
  ablation.one_object = false;
  ablation.target = "thesis-ablation";
  ablation.switches = {"--cone-test", "printed"};
  CHECK(ablation.Canonical().ends_with("backend=emu switches=[--cone-test printed]"));
  CHECK(ablation.RenderArgs().find(" --cone-test printed") != std::string::npos);
  Result r;
  r.key = "k";
  r.config = ablation;
  CHECK(ResultFromJson(ToJson(r), "a result").config.switches == ablation.switches);
  // Hunt and Mark's fitted grid: the regular grid's cell count names its results, is passed to
  // render and survives the result file; without it the grid configurations keep their keys.
  Config grid;
  grid.target = "hunt-mark";
  grid.scene = "SPONZA-SOFT";
  grid.scene_file = "sponza-soft.json";
  grid.algo = "grid";
  grid.bounces = 0;
  grid.grid_area = "regular";
  CHECK(grid.Canonical() ==
        "target=hunt-mark scene=SPONZA-SOFT file=sponza-soft.json algo=grid grid area=regular bounces=0 size=512x512 objects=flat "
        "backend=emu");
  grid.grid_regular_cells = 160000;
  CHECK(grid.Canonical().find("grid area=regular regular-cells=160000 bounces=0") != std::string::npos);
  CHECK(grid.RenderArgs().find(" --grid-regular-cells 160000") != std::string::npos);
  r.config = grid;
  CHECK(ResultFromJson(ToJson(r), "a result").config.grid_regular_cells == 160000u);
  // A configuration's own thread count (hunt-mark's scaling) names its results too.
  grid.threads = 1;
  CHECK(grid.Canonical().ends_with("backend=emu threads=1"));
  CHECK(grid.RenderArgs().find(" --threads 1") != std::string::npos);
  CHECK(grid.Name().ends_with(" threads 1"));
  r.config = grid;
  CHECK(ResultFromJson(ToJson(r), "a result").config.threads == 1);
  // Embree beside the grids (tables 2-4): its own key and command line.
  Config bvh = grid;
  bvh.algo = "embree", bvh.primary = true, bvh.threads = 0, bvh.grid_area.clear(), bvh.grid_regular_cells = 0;
  CHECK(bvh.Canonical() ==
        "target=hunt-mark scene=SPONZA-SOFT file=sponza-soft.json algo=embree bvh primary=embree bounces=0 size=512x512 objects=flat "
        "backend=emu");
  CHECK(bvh.RenderArgs().find(" --algo embree --primary embree --bounces 0") != std::string::npos);
  CHECK(bvh.Name() == "SPONZA-SOFT embree primary 512x512");
}

TEST_CASE("reproduce toczek: the node definition is the traversal event closest to the fit row, never a scale") {
  // |ln| distances: 58.8 -> 3.31, 114,940 -> 4.27, 73.9 -> 3.08 from 1,603.8: warp steps.
  CHECK(FitNodeDefinition({58.8, 114940.5, 73.9}, 1603.8) == NodeDefinition::kWarpSteps);
  // Above the target counts by the same log distance: 3,207.6 (x2) beats 400 (x1/4).
  CHECK(FitNodeDefinition({400.0, 3207.6, 10.0}, 1603.8) == NodeDefinition::kEntries);
  // A definition the walks did not count (negative) is never chosen; a tie keeps the earlier.
  CHECK(FitNodeDefinition({100.0, -1.0, 100.0}, 1603.8) == NodeDefinition::kTested);
  CHECK(FitNodeDefinition({1.0, -1.0, 1600.0}, 1603.8) == NodeDefinition::kWarpSteps);
  CHECK(std::string(NodeDefinitionName(NodeDefinition::kEntries)) == "list entries passed");
}

TEST_CASE("reproduce: merge takes every shard of one run exactly once") {
  const std::vector<std::string> keys = {"c", "a", "b", "d"};
  auto shard = [&](int i, int n) { return MakeManifest(keys, {i, n}); };
  CHECK(shard(0, 2).keys == std::vector<std::string>{"a", "b", "c", "d"});
  CHECK(shard(1, 2).Slice() == std::vector<std::string>{"b", "d"});
  CHECK_NOTHROW(CheckCoverage({{"s0", shard(0, 2)}, {"s1", shard(1, 2)}}));
  CHECK_THROWS_WITH_AS(CheckCoverage({{"s0", shard(0, 3)}, {"s2", shard(2, 3)}}), "shard 1/3 is missing", InputError);
  CHECK_THROWS_WITH_AS(CheckCoverage({{"s0", shard(0, 2)}, {"t0", shard(0, 2)}}), "shard 0/2 given twice: s0 and t0", InputError);
  CHECK_THROWS_WITH_AS(CheckCoverage({{"s0", shard(0, 2)}, {"s1", shard(1, 3)}}), "s1: shard 1/3, but s0 is one of 2", InputError);
  Manifest other = MakeManifest({"a", "b"}, {1, 2});
  CHECK_THROWS_WITH_AS(CheckCoverage({{"s0", shard(0, 2)}, {"x", other}}),
                       doctest::Contains("x: holds another run than s0"), InputError);
  CHECK_THROWS_WITH_AS(ParseShard("2/2"), "--shard '2/2': needs 0 <= I < N", InputError);
  CHECK_THROWS_AS(ParseShard("a/2"), InputError);
  CHECK(ParseShard("1/4") == Shard{1, 4});
}

}  // namespace
}  // namespace rayspace::reproduce

namespace rayspace::reproduce {
namespace {

// A frame whose counts follow from the configuration alone, so that any schedule gives the same.
FrameOutput FakeFrame(const Config& c, const Scene&, const SceneBuffers&) {
  FrameOutput out;
  TypeCounts& t = out.counts.types["shadow"];
  // RAH's nodes hit more than CRSH's, so that RAH's total is the larger counted either way.
  const std::uint64_t hits = c.algo == "crsh" ? 7 : 9;
  for (int L = 1; L <= c.levels; ++L) t.levels.push_back({static_cast<std::uint64_t>(100 * L + c.subdivision), hits});
  t.rays = 64;
  t.brute_force = 64 * 10;
  t.total = 200 + static_cast<std::uint64_t>(c.subdivision + c.levels + (c.algo == "crsh" ? 0 : 50));
  out.counts.total = t.total;
  out.counts.brute_force = t.brute_force;
  out.statistics = {{"total_tests", t.total}};
  out.timings = {{"frame_ms", 1.0}, {"phases", nlohmann::json::array()}};
  return out;
}

std::string ReportOf(const std::filesystem::path& dir, const std::vector<Planned>& planned, int jobs) {
  std::filesystem::remove_all(dir);
  RunPlanned(planned, {dir, jobs, 0, false}, FakeFrame);
  std::vector<Result> results;
  for (const Planned& p : planned) results.push_back(*ReadResult(dir, p.key));
  WriteReport(dir, results);
  std::ifstream in(dir / "report.md");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_CASE("reproduce: the report does not depend on --jobs, and a failing frame stops the run") {
  const LoadedScene scene;
  std::vector<Planned> planned;
  for (const Config& c : ThesisConfigs("no-such-dir", 16, 16))
    planned.push_back({c, ResultKey("digest", c.Canonical(), Version()), &scene});
  const std::filesystem::path tmp = std::filesystem::temp_directory_path() / "rayspace_reproduce_test";
  const std::string one = ReportOf(tmp / "one", planned, 1);
  CHECK(one.find("| CRSH total < RAH total | sec. 4.4, every scene and configuration") != std::string::npos);
  CHECK(one.find("| 18 of 18 | 18 of 18 |") != std::string::npos);
  CHECK(one.find("## Relations the project adds (not stated by the papers)") != std::string::npos);
  CHECK(ReportOf(tmp / "three", planned, 3) == one);
  const FrameFn failing = [](const Config& c, const Scene& s, const SceneBuffers& b) {
    if (c.algo == "rah-quadtree") throw InputError("no quadtree here");
    return FakeFrame(c, s, b);
  };
  CHECK_THROWS_WITH_AS(RunPlanned(planned, {tmp / "failing", 2, 0, false}, failing), "no quadtree here", InputError);
  std::filesystem::remove_all(tmp);
}

}  // namespace
}  // namespace rayspace::reproduce

namespace rayspace::reproduce {
namespace {

Result Timed(const std::string& scene, const std::string& algo, const std::vector<std::pair<std::string, double>>& passes) {
  Result r;
  r.config.target = "hunt-mark";
  r.config.scene = scene;
  r.config.algo = algo;
  r.config.primary = true;
  r.config.bounces = 0;
  TypeCounts& t = r.counts.types["shadow"];
  t.rays = 100;
  t.brute_force = 100 * 1000;  // 1,000 triangles
  nlohmann::json ps = nlohmann::json::array();
  for (const auto& [name, ms] : passes) ps.push_back({{"pass", name}, {"ms", ms}});
  r.timings = {{"passes", ps}};
  return r;
}

}  // namespace

TEST_CASE("reproduce hunt-mark: tables 2-4 set the grids' times beside Embree's and the raster's, and judge each relation") {
  // The grids: eye build 10 + eye trace 10, lights' build 20 + shadow trace 20; the raster 5 ms.
  const std::vector<std::pair<std::string, double>> grid = {{"grid.build.eye", 10}, {"grid.trace.primary.b0", 10}, {"grid.build", 20},
                                                            {"grid.trace.shadow.b0", 20}, {"raster", 5}};
  const Result conf = Timed("CONFERENCE", "grid", grid), bunny = Timed("BUNNY-69K", "grid", grid);
  // Embree: built in its first batch (5 of the eye pass's 15 ms), shadows 10 ms: faster than the grids.
  const Result bvh = Timed("CONFERENCE", "embree", {{"embree.build", 5}, {"trace.primary.b0", 15}, {"trace.shadow.b0", 10}});
  const Table t = Tables234({&conf, &bunny, &bvh});
  REQUIRE(t.rows.size() == 4);  // CONFERENCE's three comparisons and BUNNY-69K's raster; BUNNY-1K has no results
  const auto find = [&](const std::string& table, const char* relation) {
    for (const auto& row : t.rows)
      if (row[0] == table && row[3] == relation) return row;
    FAIL("no row for table " << table);
    return std::vector<std::string>{};
  };
  const auto eye = find("2", kHuntFasterEye);
  CHECK(eye[4] == "20.0 ms");
  CHECK(eye[5] == "15.0 ms");  // build 5 + eye 10
  CHECK(eye[6] == "x0.75");
  CHECK(eye[7] == "fails");
  CHECK(eye[9] == "holds");  // 22 against 16
  const auto both = find("2", kHuntFasterShadow);
  CHECK(both[4] == "60.0 ms");
  CHECK(both[5] == "25.0 ms");
  CHECK(both[9] == "fails");  // 6.8 against 7.2
  const auto stat = find("3", kHuntFasterStatic);
  CHECK(stat[5] == "10.0 ms");  // the build left out
  CHECK(stat[6] == "x0.50");
  const auto z = find("4", kHuntZBuffer);
  CHECK(z[4] == "0.05 Mtri/s");  // 1,000 triangles in 20 ms
  CHECK(z[5] == "0.20 Mtri/s");  // in 5 ms
  CHECK(z[6] == "x0.25");
  CHECK(z[7] == "fails");  // outside 2x
  CHECK(z[9] == "holds");
  // The grids' eye rays as fast as the raster: within 2x holds.
  const Result quick = Timed("BUNNY-69K", "grid", {{"grid.build.eye", 2}, {"grid.trace.primary.b0", 3}, {"raster", 5}});
  const Table q = Tables234({&quick});
  REQUIRE(q.rows.size() == 1);
  CHECK(q.rows[0][6] == "x1.00");
  CHECK(q.rows[0][7] == "holds");
}

}  // namespace rayspace::reproduce

namespace rayspace::reproduce {

TEST_CASE("reproduce toczek: table 2's frame and ray rates, ours beside the published, and their relations") {
  const auto run = [](const std::string& scene, std::uint64_t triangles, double frame_ms, double trace_ms) {
    Result r;
    r.config.target = "toczek";
    r.config.scene = scene;
    r.config.algo = "tl";
    r.config.lists = 6;
    r.config.node_order = "earliest-first";
    TypeCounts& t = r.counts.types["shadow"];
    t.rays = 1000;
    t.brute_force = 1000 * triangles;
    r.timings = {{"frame_ms", frame_ms}, {"passes", nlohmann::json::array({{{"pass", "trace.shadow.b0"}, {"ms", trace_ms}}})}};
    return r;
  };
  // 1,000 rays: 1 ms of trace is 1 M rays/s.
  const Result cubes = run("CUBES", 222, 10, 1), dragon = run("DRAGON", 100002, 100, 10);
  const Table t = ToczekRatesTable({&dragon, &cubes});
  REQUIRE(t.rows.size() == ToczekTable2().size() + 2);
  CHECK(t.rows[ToczekTable2().size()][0] == "CUBES");  // ours in ToczekScenes' order
  CHECK(t.rows[ToczekTable2().size()][4] == "100.00");
  CHECK(t.rows[ToczekTable2().size()][7] == "1.00");
  const auto note = [&](const char* relation) {
    for (const std::string& n : t.notes)
      if (n.find(relation) != std::string::npos) return n;
    return std::string();
  };
  CHECK(note(kToczekRateFalls).find("ours holds (1.00 to 0.10 M rays/s); published holds") != std::string::npos);
  CHECK(note(kToczekTenTimes).find("ours holds (smallest against largest frames/s: x10.0); published holds (x9.8)") != std::string::npos);
  // The small scene 30x the large one's frame rate: not "about 10 times".
  const Result fast = run("CUBES", 222, 10, 1), slow = run("DRAGON", 100002, 300, 10);
  CHECK(ToczekRatesTable({&fast, &slow}).notes.back().find("ours fails (smallest against largest frames/s: x30.0)") != std::string::npos);
  CHECK(ToczekRatesTable({&fast}).rows.empty());  // one scene: no relation to judge
}

}  // namespace rayspace::reproduce

namespace rayspace::reproduce {

TEST_CASE("reproduce thesis-ablation: the variants score the report's fitted scene only; the fits side by side, each its own") {
  // SPONZA RAH s8 d3 on two fitted scenes, under the defaults and the last variant: the protocol-2
  // scene's totals within 15 % of the thesis's (632,408,864 printed), protocol 1's twice it.
  const auto result = [](const std::string& file, const std::vector<std::string>& switches, double total) {
    Result r;
    r.config.target = "thesis-ablation";
    r.config.scene = "SPONZA";
    r.config.scene_file = file;
    r.config.algo = "rah";
    r.config.subdivision = 8;
    r.config.levels = 3;
    r.config.switches = switches;
    r.counts.total = static_cast<std::uint64_t>(total);
    r.counts.types["shadow"].rays = 256713;
    return r;
  };
  const std::vector<std::string> last = AblationSwitches().back();
  const std::vector<Result> both = {result("sponza-thesis-fit.json", {}, 2 * 632408864.0), result("sponza-thesis-fit.json", last, 2 * 632408864.0),
                                    result("sponza-thesis-fit-2.json", {}, 632408864.0), result("sponza-thesis-fit-2.json", last, 632408864.0)};
  const Table a = AblationTable(both, ThesisPublished());
  REQUIRE(a.rows.size() == 2);  // the defaults and the last variant, of the protocol-2 scene only
  CHECK(a.rows[0][1] == "1 of 1");
  CHECK(a.rows[1][1] == "1 of 1");
  CHECK(a.notes.back().find("SPONZA (sponza-thesis-fit-2.json)") != std::string::npos);
  const Table fits = AblationFitsTable(both, ThesisPublished());
  REQUIRE(fits.rows.size() == 4);
  CHECK(fits.rows[0][0] == "sponza-thesis-fit-2.json");
  CHECK(fits.rows[0][1] == "2");
  CHECK(fits.rows[0][3] == "1 of 1");
  CHECK(fits.rows[2][0] == "sponza-thesis-fit.json");
  CHECK(fits.rows[2][1] == "1");
  CHECK(fits.rows[2][3] == "0 of 1");
  // One fit: nothing to set beside it.
  CHECK(AblationFitsTable({both[2], both[3]}, ThesisPublished()).rows.empty());
  CHECK(FitProtocolOfScene("sponza-thesis.json") == 0);
}

}  // namespace rayspace::reproduce
