#include "rayspace/reproduce/counts.h"

namespace rayspace::reproduce {

void to_json(nlohmann::json& j, const LevelCounts& l) {
  j = {{"intersections", l.intersections}, {"hits", l.hits}, {"misses", l.misses()}};
}
void from_json(const nlohmann::json& j, LevelCounts& l) {
  j.at("intersections").get_to(l.intersections);
  j.at("hits").get_to(l.hits);
}

void to_json(nlohmann::json& j, const TypeCounts& t) {
  j = {{"levels", t.levels},   {"final_tests", t.final_tests}, {"rays", t.rays}, {"brute_force_tests", t.brute_force},
       {"total_tests", t.total}, {"top_nodes_x_triangles", t.top_nodes_x_triangles}};
}
void from_json(const nlohmann::json& j, TypeCounts& t) {
  j.at("levels").get_to(t.levels);
  j.at("final_tests").get_to(t.final_tests);
  j.at("rays").get_to(t.rays);
  j.at("brute_force_tests").get_to(t.brute_force);
  j.at("total_tests").get_to(t.total);
  j.at("top_nodes_x_triangles").get_to(t.top_nodes_x_triangles);
}

void to_json(nlohmann::json& j, const Counts& c) {
  j = {{"per_type", c.types}, {"total_tests", c.total}, {"brute_force_tests", c.brute_force}};
}
void from_json(const nlohmann::json& j, Counts& c) {
  j.at("per_type").get_to(c.types);
  j.at("total_tests").get_to(c.total);
  j.at("brute_force_tests").get_to(c.brute_force);
}

Counts SlotAccounting(const Counts& c, int subdivision) {
  Counts out = c;
  const auto s = static_cast<std::uint64_t>(subdivision);
  out.total = 0;
  for (auto& [name, t] : out.types) {
    if (t.levels.empty()) {
      out.total += t.total;
      continue;
    }
    for (std::size_t L = 0; L + 1 < t.levels.size(); ++L) t.levels[L].intersections = t.levels[L + 1].hits * s;
    t.final_tests = t.levels[0].hits * s;
    t.total = t.final_tests;
    for (const LevelCounts& l : t.levels) t.total += l.intersections;
    out.total += t.total;
  }
  return out;
}

std::string ThesisRayType(const std::string& type) {
  if (type == "shadow") return "SH";
  if (type == "reflection") return "RE";
  if (type == "refraction") return "RF";
  return type;
}

}  // namespace rayspace::reproduce
