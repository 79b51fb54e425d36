// One configuration's measured counts in the thesis's terms, as stored in its result file.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace rayspace::reproduce {

struct LevelCounts {
  std::uint64_t intersections = 0, hits = 0;
  std::uint64_t misses() const { return intersections - hits; }
};

struct TypeCounts {
  std::vector<LevelCounts> levels;  // index L-1 for level L (level `depth` is the top)
  std::uint64_t final_tests = 0, rays = 0, brute_force = 0, total = 0;
  // Sum over the type's batches of ceil(rays / subdivision^depth) x triangles: what the top level
  // tests when every top node meets every triangle.
  std::uint64_t top_nodes_x_triangles = 0;
};

struct Counts {
  std::map<std::string, TypeCounts> types;  // by ray type: shadow, reflection, refraction
  std::uint64_t total = 0, brute_force = 0;
};

void to_json(nlohmann::json& j, const LevelCounts& l);
void from_json(const nlohmann::json& j, LevelCounts& l);
void to_json(nlohmann::json& j, const TypeCounts& t);
void from_json(const nlohmann::json& j, TypeCounts& t);
void to_json(nlohmann::json& j, const Counts& c);
void from_json(const nlohmann::json& j, Counts& c);

// The counts as the thesis's tables count (35 of its 36 totals follow it): each hit of a node at level
// L+1 is followed by `subdivision` tests at level L, and each level-1 hit by `subdivision` final tests,
// whether the child slot holds a node (a ray) or is empty; an empty slot's tests are misses. The last
// node of a batch holds fewer children (SPONZA s16 d4: 4 top nodes, 63 nodes below them, and the
// thesis's 4,252,800 level-3 tests = 64 x 66,450). Hits, rays and brute force are unchanged.
Counts SlotAccounting(const Counts& c, int subdivision);

// The thesis's short name of a ray type (SH, RE, RF), and back.
std::string ThesisRayType(const std::string& type);

}  // namespace rayspace::reproduce
