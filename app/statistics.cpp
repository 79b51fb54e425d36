#include "statistics.h"

#include <nlohmann/json.hpp>

#include "rayspace/error.h"

namespace rayspace::app {

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
    t.rays += b.rays;
    t.brute_force += b.BruteForce();
    t.object_sphere_tests += b.object_sphere_tests;
    t.object_tree_tests += b.object_tree_tests;
    s.total += b.Total();
    s.brute_force += b.BruteForce();
    s.object_sphere_tests += b.object_sphere_tests;
    s.object_tree_tests += b.object_tree_tests;
  }
  // The accounting identity, recomputed from the per-type sums.
  std::uint64_t check = 0;
  for (const auto& [kind, t] : s.types) {
    check += t.final_tests + t.object_tree_tests;
    for (const emu::LevelStats& l : t.levels) check += l.intersections;
  }
  RS_CHECK_MSG(check == s.total, "total {} != levels + object-tree tests + final tests {}", s.total, check);
  return s;
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

void Statistics::ToJson(nlohmann::json& j) const {
  nlohmann::json levels = nlohmann::json::array(), finals = nlohmann::json::object(), batch_list = nlohmann::json::array();
  for (const auto& [kind, t] : types) {
    for (std::size_t L = t.levels.size(); L-- > 0;) {
      const emu::LevelStats& l = t.levels[L];
      levels.push_back({{"ray_type", emu::RayKindName(kind)}, {"level", L + 1}, {"intersections", l.intersections},
                        {"hits", l.hits}, {"misses", l.intersections - l.hits}});
    }
    finals[emu::RayKindName(kind)] = t.final_tests;
  }
  for (const emu::BatchStats& b : batches) {
    nlohmann::json bl = nlohmann::json::array();
    for (std::size_t L = b.levels.size(); L-- > 0;)
      bl.push_back({{"level", L + 1}, {"intersections", b.levels[L].intersections}, {"hits", b.levels[L].hits},
                    {"misses", b.levels[L].intersections - b.levels[L].hits}});
    batch_list.push_back({{"batch", b.batch}, {"ray_type", emu::RayKindName(b.kind)}, {"bounce", b.bounce},
                          {"rays", b.rays}, {"levels", bl}, {"final_tests", b.final_tests}, {"total_tests", b.Total()},
                          {"object_sphere_tests", b.object_sphere_tests}, {"object_sphere_hits", b.object_sphere_hits},
                          {"object_tree_tests", b.object_tree_tests}, {"object_tree_hits", b.object_tree_hits},
                          {"triangle_batches", b.triangle_batches}, {"overflow_splits", b.overflow_splits}});
  }
  j["levels"] = levels;
  j["final_tests"] = finals;
  j["total_tests"] = total;
  j["brute_force_tests"] = brute_force;
  j["object_sphere_tests"] = object_sphere_tests;
  j["object_tree_tests"] = object_tree_tests;
  j["batches"] = batch_list;
}

void Statistics::Print(std::FILE* out) const {
  static const char* kShort[3] = {"SH", "RE", "RF"};
  const double bf = brute_force > 0 ? static_cast<double>(brute_force) : 1.0;
  if (hierarchy && depth > 0) {
    std::fprintf(out, "  %-22s", "");
    for (int L = depth; L >= 1; --L) std::fprintf(out, " %16s", ("LEVEL " + std::to_string(L)).c_str());
    std::fprintf(out, "\n");
    for (const auto& [kind, t] : types) {
      const char* rows[3] = {"INTERSECTIONS", "MISSES", "HITS"};
      for (int r = 0; r < 3; ++r) {
        std::fprintf(out, "  # %s %-17s", kShort[kind], rows[r]);
        for (int L = depth; L >= 1; --L) {
          const emu::LevelStats& l = t.levels[L - 1];
          const std::uint64_t v = r == 0 ? l.intersections : r == 1 ? l.intersections - l.hits : l.hits;
          std::fprintf(out, " %16llu", static_cast<unsigned long long>(v));
        }
        std::fprintf(out, "\n");
      }
      std::fprintf(out, "  # %s %-17s", kShort[kind], "% OF BRUTE FORCE");
      for (int L = depth; L >= 1; --L)
        std::fprintf(out, " %15.2f%%", 100.0 * static_cast<double>(t.levels[L - 1].intersections) / bf);
      std::fprintf(out, "\n  # %s %-17s %16llu\n", kShort[kind], "FINAL TESTS", static_cast<unsigned long long>(t.final_tests));
    }
    if (object_sphere_tests) std::fprintf(out, "  object-sphere tests   %16llu\n", static_cast<unsigned long long>(object_sphere_tests));
    if (object_tree_tests)
      std::fprintf(out, "  object-tree tests     %16llu (in the total)\n", static_cast<unsigned long long>(object_tree_tests));
  }
  std::fprintf(out, "  total tests           %16llu (%.2f%% of brute force %llu)\n", static_cast<unsigned long long>(total),
               100.0 * static_cast<double>(total) / bf, static_cast<unsigned long long>(brute_force));
}

}  // namespace rayspace::app
