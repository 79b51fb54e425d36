// The CRSH thesis's published tables (refs/papers/crsh-thesis), embedded in the binary at build time so
// that `rayspace reproduce` needs no source tree.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

namespace rayspace::reproduce {

// One hierarchy configuration of the thesis: subdivision x depth (rayspace's --levels).
struct HierarchyShape {
  int subdivision = 8, depth = 2;
  auto operator<=>(const HierarchyShape&) const = default;
};

struct PublishedTiming {
  std::string scene, algorithm, phase;
  double ms_per_frame = 0.0, total_ms_58_frames = 0.0, relative_percent = 0.0;
};

struct Published {
  // (subdivision, depth, scene, algorithm, ray type SH|RE, level, metric) -> count.
  using LevelKey = std::tuple<int, int, std::string, std::string, std::string, int, std::string>;
  std::map<LevelKey, std::uint64_t> levels;
  // (subdivision, depth, scene, algorithm BRUTE|RAH|CRSH) -> (total, percent of brute force).
  using TotalKey = std::tuple<int, int, std::string, std::string>;
  std::map<TotalKey, std::pair<std::uint64_t, double>> totals;
  std::vector<PublishedTiming> timings;

  // The published count, or nullptr when the thesis prints none.
  const std::uint64_t* Level(HierarchyShape s, const std::string& scene, const std::string& algorithm,
                             const std::string& ray_type, int level, const std::string& metric) const;
  const std::pair<std::uint64_t, double>* Total(HierarchyShape s, const std::string& scene, const std::string& algorithm) const;
};

// Parses the three CSV files' text; `name` prefixes their names in errors. Throws InputError naming
// the file and line of a malformed row.
Published ParsePublished(std::string_view levels_csv, std::string_view totals_csv, std::string_view timings_csv,
                         const std::string& name = "refs/papers/crsh-thesis/");

// The thesis's tables as embedded in this binary.
const Published& ThesisPublished();

// The thesis's frames (512x512) per scene, from its captions: rays per ray type and the triangles
// brute force / rays implies.
struct PublishedScene {
  std::uint64_t shadow_rays = 0, reflection_rays = 0, triangles = 0;
};
const PublishedScene& ThesisScene(const std::string& scene);

}  // namespace rayspace::reproduce
