#include "rayspace/reproduce/relations.h"

#include <fmt/format.h>

namespace rayspace::reproduce {
namespace {

Outcome Less(std::uint64_t a, std::uint64_t b) {
  const bool holds = a < b;
  return {holds, fmt::format("{} {} {}", Thousands(a), holds ? "<" : ">=", Thousands(b))};
}

Outcome Equal(std::uint64_t a, std::uint64_t b) {
  const bool holds = a == b;
  return {holds, fmt::format("{} {} {}", Thousands(a), holds ? "=" : "!=", Thousands(b))};
}

}  // namespace

std::string Thousands(std::uint64_t v) {
  std::string digits = std::to_string(v), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string Verdict(const std::optional<Outcome>& o) { return !o ? "n/a" : o->holds ? "holds" : "fails"; }

Outcome CrshBelowRah(const Measurement& rah, const Measurement& crsh) { return Less(crsh.total, rah.total); }
Outcome Below(const Measurement& m, const Measurement& reference) { return Less(m.total, reference.total); }
Outcome Above(const Measurement& m, const Measurement& reference) {
  const bool holds = m.total > reference.total;
  return {holds, fmt::format("{} {} {}", Thousands(m.total), holds ? ">" : "<=", Thousands(reference.total))};
}
Outcome BelowBrute(const Measurement& m) { return Less(m.total, m.brute_force); }

Outcome RahTopLevel(const Measurement& rah, int depth) {
  std::uint64_t top = 0, expected = 0;
  for (const auto& [type, levels] : rah.levels)
    if (static_cast<int>(levels.size()) >= depth) top += levels[depth - 1].intersections;
  for (const auto& [type, n] : rah.top_nodes_x_triangles) expected += n;
  return Equal(top, expected);
}

std::uint64_t AccountedTotal(const Measurement& m, int subdivision) {
  std::uint64_t sum = 0;
  for (const auto& [type, levels] : m.levels) {
    for (const LevelCounts& l : levels) sum += l.intersections;
    if (!levels.empty()) sum += levels[0].hits * static_cast<std::uint64_t>(subdivision);
  }
  return sum;
}

Outcome Identity(const Measurement& m, int subdivision) { return Equal(m.total, AccountedTotal(m, subdivision)); }

std::optional<Measurement> PublishedMeasurement(const Published& p, HierarchyShape s, const std::string& scene,
                                                const std::string& algorithm) {
  const auto* total = p.Total(s, scene, algorithm);
  const auto* brute = p.Total(s, scene, "BRUTE");
  if (!total || !brute) return std::nullopt;
  Measurement m;
  m.total = total->first;
  m.brute_force = brute->first;
  const PublishedScene& ps = ThesisScene(scene);
  std::uint64_t top_rays = 1;
  for (int L = 0; L < s.depth; ++L) top_rays *= static_cast<std::uint64_t>(s.subdivision);
  for (const auto& [type, rays] : {std::pair<std::string, std::uint64_t>{"SH", ps.shadow_rays}, {"RE", ps.reflection_rays}}) {
    if (rays == 0) continue;
    std::vector<LevelCounts>& levels = m.levels[type];
    levels.resize(s.depth);
    for (int L = 1; L <= s.depth; ++L) {
      const std::uint64_t* in = p.Level(s, scene, algorithm, type, L, "intersections");
      const std::uint64_t* hits = p.Level(s, scene, algorithm, type, L, "hits");
      levels[L - 1] = {in ? *in : 0, hits ? *hits : 0};
    }
    m.top_nodes_x_triangles[type] = (rays + top_rays - 1) / top_rays * ps.triangles;
  }
  return m;
}

Measurement OurMeasurement(const Counts& c) {
  Measurement m;
  m.total = c.total;
  m.brute_force = c.brute_force;
  for (const auto& [type, t] : c.types) {
    m.levels[ThesisRayType(type)] = t.levels;
    m.top_nodes_x_triangles[ThesisRayType(type)] = t.top_nodes_x_triangles;
  }
  return m;
}

}  // namespace rayspace::reproduce
