#include "rayspace/frame/statistics.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "rayspace/error.h"

namespace rayspace::app {

std::uint64_t Statistics::PerType::Total() const {
  std::uint64_t sum = final_tests + leaf_sphere_tests + tl_sphere_tests + ray_level.intersections;
  for (const emu::LevelStats& l : levels) sum += l.intersections;
  return sum;
}

Statistics CollectStatistics(const std::vector<emu::BatchStats>& batches) {
  Statistics s;
  s.hierarchy = true;
  s.batches = batches;
  for (const emu::BatchStats& b : batches) {
    s.depth = std::max(s.depth, static_cast<int>(b.levels.size()));
    Statistics::PerType& t = s.types[b.kind];
    t.levels.resize(b.levels.size());
    for (std::size_t L = 0; L < b.levels.size(); ++L) {
      t.levels[L].intersections += b.levels[L].intersections;
      t.levels[L].hits += b.levels[L].hits;
    }
    t.final_tests += b.final_tests;
    t.leaf_sphere_tests += b.leaf_sphere_tests;
    s.leaf_sphere_tests += b.leaf_sphere_tests;
    t.rays += b.rays;
    t.brute_force += b.BruteForce();
    t.object_sphere_tests += b.object_sphere_tests;
    t.ray_level.intersections += b.ray_level.intersections;
    t.ray_level.hits += b.ray_level.hits;
    s.total += b.Total();
    s.brute_force += b.BruteForce();
    s.object_sphere_tests += b.object_sphere_tests;
    s.object_tree = s.object_tree || b.tree_rounds > 0;
    s.object_levels.resize(std::max(s.object_levels.size(), b.object_levels.size()));
    for (std::size_t d = 0; d < b.object_levels.size(); ++d) {
      s.object_levels[d].intersections += b.object_levels[d].intersections;
      s.object_levels[d].hits += b.object_levels[d].hits;
    }
    s.object_triangles.intersections += b.object_triangles.intersections;
    s.object_triangles.hits += b.object_triangles.hits;
  }
  // The accounting identity, recomputed from the per-type sums.
  std::uint64_t check = 0;
  for (const auto& [kind, t] : s.types) check += t.Total();
  RS_CHECK_MSG(check == s.total, "total {} != levels + ray tests + final tests {}", s.total, check);
  // --objects tree: a tree batch's tests counted again by their object side.
  for (const emu::BatchStats& b : batches) {
    if (!b.object_tree) continue;
    std::uint64_t by_object = b.object_triangles.intersections, by_cone = b.ray_level.intersections;
    for (const emu::LevelStats& l : b.object_levels) by_object += l.intersections;
    for (const emu::LevelStats& l : b.levels) by_cone += l.intersections;
    RS_CHECK_MSG(by_object == by_cone, "batch {}: tree tests by object side {} != by cone level {}", b.batch, by_object, by_cone);
  }
  return s;
}

Statistics TlStatistics(const emu::TlTracer& tracer, std::size_t triangles) {
  Statistics s;
  s.tl = true;
  s.tl_shape = tracer.Shape();
  s.tl_lists.resize(s.tl_shape.lists);
  for (const emu::TlBatchStats& b : tracer.Stats()) {
    Statistics::PerType& t = s.types[b.kind];
    t.rays += b.rays;
    t.brute_force += b.rays * triangles;
    t.final_tests += b.triangles;
    t.tl_sphere_tests += b.spheres;
    t.tl_warp_steps += b.warp_steps;
    t.tl_entries += b.entries;
    if (b.rays && !b.has_entries) t.tl_entries_unknown = true;
    for (std::size_t k = 0; k < b.list_rays.size() && k < s.tl_lists.size(); ++k) {
      s.tl_lists[k].rays += b.list_rays[k];
      s.tl_lists[k].spheres += b.list_spheres[k];
      s.tl_lists[k].triangles += b.list_triangles[k];
    }
  }
  for (const auto& [kind, t] : s.types) {
    s.total += t.Total();
    s.brute_force += t.brute_force;
  }
  return s;
}

Statistics GridStatistics(const emu::GridTracer& tracer, std::size_t triangles) {
  Statistics s;
  s.grid = true;
  s.grid_build_ms = tracer.BuildMs();
  for (const emu::GridBatchStats& b : tracer.Stats()) {
    Statistics::PerType& t = s.types[b.kind];
    t.rays += b.rays;
    t.brute_force += b.rays * triangles;
    t.final_tests += b.tests;
    t.grid_steps += b.steps;
    t.grid_perspective_rays += b.perspective_rays;
    t.grid_unoccluded_perspective_rays += b.unoccluded_perspective_rays;
    t.grid_skipped_rays += b.skipped_rays;
    t.grid_area_rays += b.area_rays;
    t.grid_area_steps += b.area_steps;
    t.grid_area_tests += b.area_tests;
    t.grid_area_core_steps += b.area_core_steps;
    if (b.area_rays && !b.has_core_steps) t.grid_area_core_unknown = true;
    t.grid_volume_rays += b.volume_rays;
  }
  for (const auto& [kind, t] : s.types) {
    s.total += t.Total();
    s.brute_force += t.brute_force;
  }
  return s;
}

int ShareDecimals(double percent) {
  return percent > 0 ? std::clamp(2 - static_cast<int>(std::floor(std::log10(percent))), 2, 9) : 2;
}

Statistics BruteStatistics(const emu::FrameResult& frame, std::size_t triangles) {
  Statistics s;
  for (std::uint32_t k = 0; k < 3; ++k) {
    std::uint64_t rays = 0;
    for (std::uint64_t n : frame.rays[k]) rays += n;
    if (rays == 0) continue;
    Statistics::PerType& t = s.types[k];
    t.rays = rays;
    t.brute_force = rays * triangles;
    t.final_tests = t.brute_force;
    s.brute_force += t.brute_force;
  }
  s.total = s.brute_force;
  return s;
}

namespace {

double Percent(std::uint64_t part, std::uint64_t whole) {
  return whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0;
}

// Per ray type: its rays, its brute force (rays x triangles) and its tests as a share of it; null
// tests and shares for a tracer that does not count its tests (Embree), as the frame's are.
nlohmann::json PerTypeJson(const std::map<std::uint32_t, Statistics::PerType>& types, std::uint64_t frame_brute_force,
                           bool tests_counted) {
  nlohmann::json j = nlohmann::json::object();
  auto counted = [tests_counted](auto v) { return tests_counted ? nlohmann::json(v) : nlohmann::json(nullptr); };
  for (const auto& [kind, t] : types)
    j[emu::RayKindName(kind)] = {{"rays", t.rays},
                                 {"brute_force_tests", t.brute_force},
                                 {"total_tests", counted(t.Total())},
                                 {"percent_of_brute_force", counted(Percent(t.Total(), t.brute_force))},
                                 {"percent_of_frame_brute_force", counted(Percent(t.Total(), frame_brute_force))}};
  return j;
}

nlohmann::json LevelJson(const emu::LevelStats& l) {
  return {{"intersections", l.intersections}, {"hits", l.hits}, {"misses", l.intersections - l.hits}};
}

// --objects tree: the rays' own tests, and every test by its object side.
nlohmann::json TreeJson(const emu::LevelStats& rays, const std::vector<emu::LevelStats>& object_levels, const emu::LevelStats& triangles,
                        std::uint64_t rounds) {
  nlohmann::json depths = nlohmann::json::array();
  for (std::size_t d = 0; d < object_levels.size(); ++d) {
    nlohmann::json e = LevelJson(object_levels[d]);
    e["depth"] = d;
    depths.push_back(e);
  }
  return {{"rays", LevelJson(rays)}, {"object_depths", depths}, {"triangle_spheres", LevelJson(triangles)}, {"rounds", rounds}};
}

}  // namespace

namespace {

double PerRay(std::uint64_t n, std::uint64_t rays) { return rays ? static_cast<double>(n) / static_cast<double>(rays) : 0.0; }

// Per ray type: cells visited and triangles tested per ray; for point-light shadow rays the share that
// went through a perspective grid and, of those not occluded, the share the cells' least distance
// spared every test (Hunt and Mark: up to 90 %).
nlohmann::json GridJson(const Statistics& s) {
  nlohmann::json types = nlohmann::json::object();
  for (const auto& [kind, t] : s.types) {
    nlohmann::json one = {{"rays", t.rays},
                          {"steps", t.grid_steps},
                          {"triangle_tests", t.final_tests},
                          {"steps_per_ray", PerRay(t.grid_steps, t.rays)},
                          {"tests_per_ray", PerRay(t.final_tests, t.rays)}};
    if (t.grid_perspective_rays) one["perspective_rays"] = t.grid_perspective_rays;
    if (t.grid_perspective_rays && kind == layout::kRayShadow) {
      one["unoccluded_perspective_rays"] = t.grid_unoccluded_perspective_rays;
      one["rays_without_tests"] = t.grid_skipped_rays;
      one["unoccluded_without_tests_fraction"] = PerRay(t.grid_skipped_rays, t.grid_unoccluded_perspective_rays);
    }
    // Area-light shadow rays (Hunt and Mark's Table 5: cells per soft-shadow ray, 3D perspective
    // grid against a regular grid).
    if (t.grid_volume_rays && !t.grid_area_rays) one["through_3d_perspective_grid"] = t.grid_volume_rays;  // --grid-secondary perspective
    if (t.grid_area_rays)
      one["area_light_rays"] = {{"rays", t.grid_area_rays},
                                {"through_3d_perspective_grid", t.grid_volume_rays},
                                {"steps_per_ray", PerRay(t.grid_area_steps, t.grid_area_rays)},
                                {"tests_per_ray", PerRay(t.grid_area_tests, t.grid_area_rays)}};
    // The cells of the lights' core cubes (regular cells walked before the faces' cells), counted by
    // the emulator's walk.
    if (t.grid_area_rays && t.grid_volume_rays && !t.grid_area_core_unknown) {
      one["area_light_rays"]["core_steps_per_ray"] = PerRay(t.grid_area_core_steps, t.grid_area_rays);
      one["area_light_rays"]["face_steps_per_ray"] = PerRay(t.grid_area_steps - t.grid_area_core_steps, t.grid_area_rays);
    }
    types[emu::RayKindName(kind)] = one;
  }
  return {{"build_ms", s.grid_build_ms}, {"per_type", types}};
}

// The lists' shape and memory, then per ray type and per list the elements tested per ray.
nlohmann::json TlJson(const Statistics& s) {
  const emu::TlShape& sh = s.tl_shape;
  nlohmann::json types = nlohmann::json::object(), lists = nlohmann::json::array();
  for (const auto& [kind, t] : s.types) {
    nlohmann::json one = {{"rays", t.rays},
                          {"sphere_tests", t.tl_sphere_tests},
                          {"triangle_tests", t.final_tests},
                          {"spheres_per_ray", PerRay(t.tl_sphere_tests, t.rays)},
                          {"triangles_per_ray", PerRay(t.final_tests, t.rays)},
                          // Each ray charged its 32-ray warp's longest walk (elements tested).
                          {"warp_steps", t.tl_warp_steps},
                          {"warp_steps_per_ray", PerRay(t.tl_warp_steps, t.rays)}};
    // The list entries passed, tested or skipped by an escape (the emulator's walks count them).
    if (!t.tl_entries_unknown) one["entries"] = t.tl_entries, one["entries_per_ray"] = PerRay(t.tl_entries, t.rays);
    types[emu::RayKindName(kind)] = std::move(one);
  }
  std::uint64_t held = 0;  // elements over all lists
  for (std::size_t k = 0; k < s.tl_lists.size(); ++k) {
    const Statistics::TlList& l = s.tl_lists[k];
    nlohmann::json one = {{"rays", l.rays},
                          {"sphere_tests", l.spheres},
                          {"triangle_tests", l.triangles},
                          {"elements_per_ray", PerRay(l.spheres + l.triangles, l.rays)}};
    if (k < sh.list_elements.size()) {
      held += sh.list_elements[k];
      one["elements"] = sh.list_elements[k];
      one["culled_triangles"] = sh.list_culled[k];
      one["culled_fraction"] = PerRay(sh.list_culled[k], sh.triangle_refs);
    }
    lists.push_back(std::move(one));
  }
  const std::uint64_t tree = std::uint64_t{sh.nodes} + sh.triangle_refs;
  // The paper's "redundancy": how many copies of the tree the K lists hold together.
  return {{"lists", sh.lists},
          {"backface_culling", sh.culled},
          {"polygon_heads", sh.heads == layout::kTlHeadsRegular ? "regular" : sh.heads == layout::kTlHeadsSimple ? "simple" : "off"},
          {"window_bytes", sh.window_bytes},
          {"tree_nodes", sh.nodes},
          {"triangle_references", sh.triangle_refs},
          {"elements_per_list", tree},
          {"elements_in_lists", held},
          {"copies_of_tree", tree ? static_cast<double>(held) / static_cast<double>(tree) : 0.0},
          {"bytes", sh.bytes},
          {"per_type", types},
          {"per_list", lists}};
}

}  // namespace

void Statistics::ToJson(nlohmann::json& j) const {
  nlohmann::json levels = nlohmann::json::array(), finals = nlohmann::json::object(), batch_list = nlohmann::json::array();
  nlohmann::json leaf_spheres = nlohmann::json::object();
  for (const auto& [kind, t] : types) {
    for (std::size_t L = t.levels.size(); L-- > 0;) {
      const emu::LevelStats& l = t.levels[L];
      levels.push_back({{"ray_type", emu::RayKindName(kind)}, {"level", L + 1}, {"intersections", l.intersections},
                        {"hits", l.hits}, {"misses", l.intersections - l.hits},
                        {"percent_of_brute_force", Percent(l.intersections, t.brute_force)},
                        {"percent_of_frame_brute_force", Percent(l.intersections, brute_force)}});
    }
    finals[emu::RayKindName(kind)] = t.final_tests;
    if (leaf_sphere_tests > 0) leaf_spheres[emu::RayKindName(kind)] = t.leaf_sphere_tests;
  }
  for (const emu::BatchStats& b : batches) {
    nlohmann::json bl = nlohmann::json::array();
    for (std::size_t L = b.levels.size(); L-- > 0;)
      bl.push_back({{"level", L + 1}, {"intersections", b.levels[L].intersections}, {"hits", b.levels[L].hits},
                    {"misses", b.levels[L].intersections - b.levels[L].hits}});
    batch_list.push_back({{"batch", b.batch}, {"ray_type", emu::RayKindName(b.kind)}, {"bounce", b.bounce},
                          {"rays", b.rays}, {"levels", bl}, {"final_tests", b.final_tests}, {"total_tests", b.Total()},
                          {"object_sphere_tests", b.object_sphere_tests}, {"object_sphere_hits", b.object_sphere_hits},
                          {"triangle_batches", b.triangle_batches}, {"overflow_splits", b.overflow_splits}});
    batch_list.back()["leaf_spread"] = b.leaf_spread;
    if (leaf_sphere_tests > 0) batch_list.back()["leaf_sphere_tests"] = b.leaf_sphere_tests;
    batch_list.back()["objects"] = b.object_tree ? "tree" : "flat";
    if (b.tree_rounds > 0) batch_list.back()["object_tree"] = TreeJson(b.ray_level, b.object_levels, b.object_triangles, b.tree_rounds);
  }
  j["levels"] = levels;
  j["final_tests"] = finals;
  // --leaf-test ray-sphere only, so that the default's statistics stay as they were.
  if (leaf_sphere_tests > 0) j["leaf_sphere_tests"] = leaf_spheres;
  j["total_tests"] = tests_counted ? nlohmann::json(total) : nlohmann::json(nullptr);
  j["brute_force_tests"] = brute_force;
  j["percent_of_brute_force"] = tests_counted ? nlohmann::json(Percent(total, brute_force)) : nlohmann::json(nullptr);
  j["per_type"] = PerTypeJson(types, brute_force, tests_counted);
  j["object_sphere_tests"] = object_sphere_tests;
  if (object_tree) {
    emu::LevelStats rays;
    for (const auto& [kind, t] : types) rays.intersections += t.ray_level.intersections, rays.hits += t.ray_level.hits;
    std::uint64_t rounds = 0;
    for (const emu::BatchStats& b : batches) rounds += b.tree_rounds;
    j["object_tree"] = TreeJson(rays, object_levels, object_triangles, rounds);
  }
  j["batches"] = batch_list;
  if (tl) j["traversal_lists"] = TlJson(*this);
  if (grid) j["grids"] = GridJson(*this);
}

namespace {

const char* const kShort[4] = {"SH", "RE", "RF", "PR"};

void PrintRow(std::FILE* out, std::uint32_t kind, const char* name) { std::fprintf(out, "  # %s %-17s", kShort[kind], name); }

// One ray type's rows of the thesis's table: per level its counts and its share of brute force, the
// type's own (the thesis's) and the frame's; then its final tests and brute force.
void PrintType(std::FILE* out, std::uint32_t kind, const Statistics::PerType& t, int depth, std::uint64_t frame_bf) {
  const char* rows[3] = {"INTERSECTIONS", "MISSES", "HITS"};
  for (int r = 0; r < 3; ++r) {
    PrintRow(out, kind, rows[r]);
    for (int L = depth; L >= 1; --L) {
      const emu::LevelStats& l = t.levels[L - 1];
      const std::uint64_t v = r == 0 ? l.intersections : r == 1 ? l.intersections - l.hits : l.hits;
      std::fprintf(out, " %16llu", static_cast<unsigned long long>(v));
    }
    std::fprintf(out, "\n");
  }
  const std::pair<const char*, std::uint64_t> shares[2] = {{"% OF BRUTE FORCE", t.brute_force}, {"% OF FRAME BF", frame_bf}};
  for (const auto& [name, whole] : shares) {
    PrintRow(out, kind, name);
    for (int L = depth; L >= 1; --L) {
      const double v = Percent(t.levels[L - 1].intersections, whole);
      std::fprintf(out, " %15.*f%%", ShareDecimals(v), v);
    }
    std::fprintf(out, "\n");
  }
  if (t.leaf_sphere_tests > 0) {
    PrintRow(out, kind, "LEAF SPHERE TESTS");
    std::fprintf(out, " %16llu\n", static_cast<unsigned long long>(t.leaf_sphere_tests));
  }
  PrintRow(out, kind, "FINAL TESTS");
  std::fprintf(out, " %16llu\n", static_cast<unsigned long long>(t.final_tests));
}

void PrintObjectTree(std::FILE* out, const Statistics& s) {
  for (const auto& [kind, t] : s.types) {
    PrintRow(out, kind, "RAY TESTS");
    std::fprintf(out, " %16llu (hits %llu, in the total)\n", static_cast<unsigned long long>(t.ray_level.intersections),
                 static_cast<unsigned long long>(t.ray_level.hits));
  }
  std::fprintf(out, "  object tree, tests by depth of the tested node:");
  for (std::size_t d = 0; d < s.object_levels.size(); ++d)
    std::fprintf(out, " %zu:%llu", d, static_cast<unsigned long long>(s.object_levels[d].intersections));
  std::fprintf(out, "; triangle spheres %llu\n", static_cast<unsigned long long>(s.object_triangles.intersections));
}

}  // namespace

void Statistics::Print(std::FILE* out) const {
  if (hierarchy && depth > 0) {
    std::fprintf(out, "  %-22s", "");
    for (int L = depth; L >= 1; --L) std::fprintf(out, " %16s", ("LEVEL " + std::to_string(L)).c_str());
    std::fprintf(out, "\n");
    for (const auto& [kind, t] : types) PrintType(out, kind, t, depth, brute_force);
    if (object_sphere_tests) std::fprintf(out, "  object-sphere tests   %16llu\n", static_cast<unsigned long long>(object_sphere_tests));
    if (object_tree) PrintObjectTree(out, *this);
  }
  if (tl) {
    const emu::TlShape& sh = tl_shape;
    std::fprintf(out, "  traversal lists: %u x %u elements (%u spheres, %u triangle references), %.1f MB\n", sh.lists,
                 sh.nodes + sh.triangle_refs, sh.nodes, sh.triangle_refs, static_cast<double>(sh.bytes) / 1e6);
    for (const auto& [kind, t] : types)
      std::fprintf(out, "  %-11s %10.1f spheres + %8.1f triangles per ray\n", emu::RayKindName(kind), PerRay(t.tl_sphere_tests, t.rays),
                   PerRay(t.final_tests, t.rays));
    for (std::size_t k = 0; k < tl_lists.size(); ++k) {
      std::fprintf(out, "  list %zu: %llu rays, %.1f elements per ray", k, static_cast<unsigned long long>(tl_lists[k].rays),
                   PerRay(tl_lists[k].spheres + tl_lists[k].triangles, tl_lists[k].rays));
      if (sh.culled && k < sh.list_elements.size())
        std::fprintf(out, "; %u elements, %.1f%% of the triangles culled", sh.list_elements[k], 100.0 * PerRay(sh.list_culled[k], sh.triangle_refs));
      std::fprintf(out, "\n");
    }
  }
  if (grid)
    for (const auto& [kind, t] : types) {
      std::fprintf(out, "  %-11s %10.2f cells + %8.1f triangles per ray", emu::RayKindName(kind), PerRay(t.grid_steps, t.rays),
                   PerRay(t.final_tests, t.rays));
      if (t.grid_perspective_rays && kind == layout::kRayPrimary)
        std::fprintf(out, "; %llu through the eye's perspective grid", static_cast<unsigned long long>(t.grid_perspective_rays));
      else if (t.grid_perspective_rays)
        std::fprintf(out, "; %llu through a light's perspective grid, %.1f%% of the unoccluded ones without a test",
                     static_cast<unsigned long long>(t.grid_perspective_rays), 100.0 * PerRay(t.grid_skipped_rays, t.grid_unoccluded_perspective_rays));
      if (t.grid_volume_rays && !t.grid_area_rays)
        std::fprintf(out, "; %llu through the eye's 3D perspective grid", static_cast<unsigned long long>(t.grid_volume_rays));
      if (t.grid_area_rays)
        std::fprintf(out, "; area lights: %.2f cells + %.1f triangles per ray (%s)", PerRay(t.grid_area_steps, t.grid_area_rays),
                     PerRay(t.grid_area_tests, t.grid_area_rays), t.grid_volume_rays ? "3D perspective grid" : "regular grid");
      std::fprintf(out, "\n");
    }
  if (!tests_counted) {
    std::fprintf(out, "  total tests           not counted (Embree's BVH does not report its tests; brute force %llu)\n",
                 static_cast<unsigned long long>(brute_force));
    return;
  }
  // Each type's tests against its own brute force (rays of the type x triangles), then the frame's.
  for (const auto& [kind, t] : types)
    std::fprintf(out, "  %-11s tests %llu (%.2f%% of its brute force %llu = %llu rays x %llu triangles)\n", emu::RayKindName(kind),
                 static_cast<unsigned long long>(t.Total()), Percent(t.Total(), t.brute_force),
                 static_cast<unsigned long long>(t.brute_force), static_cast<unsigned long long>(t.rays),
                 static_cast<unsigned long long>(t.rays ? t.brute_force / t.rays : 0));
  std::fprintf(out, "  total tests           %16llu (%.2f%% of the frame's brute force %llu)\n", static_cast<unsigned long long>(total),
               Percent(total, brute_force), static_cast<unsigned long long>(brute_force));
}

}  // namespace rayspace::app
