#include "rayspace/reproduce/faithful_table.h"

#include <cmath>
#include <map>
#include <tuple>

#include <fmt/format.h>

namespace rayspace::reproduce {
namespace {

// Tests per traced ray by (faithful preset, scene, algo, subdivision, levels): totals are compared per
// ray, since our stand-ins trace other ray counts than the thesis's (office: two lights, 2.08x).
using Totals = std::map<std::tuple<std::string, std::string, std::string, int, int>, double>;

Totals MakeTotals(const std::vector<Result>& results) {
  Totals t;
  for (const Result& r : results) {
    if (r.config.quadtree()) continue;
    std::uint64_t rays = 0;
    for (const auto& [type, c] : r.counts.types) rays += c.rays;
    if (rays) t[{r.config.faithful, r.config.scene, r.config.algo, r.config.subdivision, r.config.levels}] = static_cast<double>(r.counts.total) / static_cast<double>(rays);
  }
  return t;
}

std::optional<double> Get(const Totals& t, const std::string& faithful, const std::string& scene, const char* algo, HierarchyShape s) {
  const auto it = t.find({faithful, scene, algo, s.subdivision, s.depth});
  return it == t.end() ? std::nullopt : std::optional<double>(it->second);
}

// The thesis's total over its rays (the captions' counts).
std::optional<double> PublishedTotal(const Published& p, const std::string& scene, const char* algo, HierarchyShape s) {
  const auto* v = p.Total(s, scene, algo);
  const PublishedScene& ps = ThesisScene(scene);
  const std::uint64_t rays = ps.shadow_rays + ps.reflection_rays;
  return v && rays ? std::optional<double>(static_cast<double>(v->first) / static_cast<double>(rays)) : std::nullopt;
}

std::optional<double> Quotient(std::optional<double> a, std::optional<double> b) {
  if (!a || !b || *b == 0.0) return std::nullopt;
  return *a / *b;
}

std::string Number(std::optional<double> v, const char* format) { return v ? fmt::format(fmt::runtime(format), *v) : "n/a"; }

// Ours against the published within the tolerance; nothing when either is missing.
std::optional<Outcome> Within(std::optional<double> ours, std::optional<double> pub, const char* format) {
  const std::optional<double> q = Quotient(ours, pub);
  if (!q) return std::nullopt;
  const bool holds = std::abs(*q - 1.0) <= kFaithfulTolerance;
  return Outcome{holds, fmt::format("{} vs {}: {:+.1f} %", Number(ours, format), Number(pub, format), (*q - 1.0) * 100.0)};
}

}  // namespace

Table FaithfulTable(const std::vector<Result>& results, const Published& p, std::vector<RelationRow>& relations) {
  Table t{"faithful", "Faithful to the thesis (`--faithful thesis`) beside rayspace's defaults",
          {"scene", "shape", "RAH published tests/ray", "RAH faithful tests/ray", "RAH faithful/published", "CRSH published tests/ray",
           "CRSH faithful tests/ray", "CRSH faithful/published", "CRSH/RAH published", "CRSH/RAH default", "CRSH/RAH faithful", "verdict"},
          {},
          {"Target: each faithful total per traced ray and each faithful CRSH/RAH within 15 % of the thesis's (per ray: "
           "our stand-ins trace other ray counts; the thesis's are its captions'). `--faithful thesis` is "
           "the thesis's method as printed (docs/hierarchy.md, \"Faithful to the thesis\"), and Sponza is one object as "
           "in the thesis. Where a row fails, docs/reproduce.md says why."}};
  const Totals totals = MakeTotals(results);
  for (const Result& r : results)
    if (!r.config.faithful.empty() && (r.config.width != 512 || r.config.height != 512)) {
      t.notes.push_back(fmt::format("These frames are {}x{}, not the thesis's 512x512: tests per ray depend on the frame's "
                                    "size, so only a `--full` run compares them.", r.config.width, r.config.height));
      break;
    }
  for (const SceneChoice& sc : ThesisScenes())
    for (const auto& [sub, depth] : ThesisShapes()) {
      const HierarchyShape s{sub, depth};
      const auto rah_pub = PublishedTotal(p, sc.paper, "RAH", s), crsh_pub = PublishedTotal(p, sc.paper, "CRSH", s);
      const auto rah = Get(totals, "thesis", sc.paper, "rah", s), crsh = Get(totals, "thesis", sc.paper, "crsh", s);
      if (!rah && !crsh) continue;
      const auto ratio_pub = Quotient(crsh_pub, rah_pub), ratio = Quotient(crsh, rah);
      const auto ratio_default = Quotient(Get(totals, "", sc.paper, "crsh", s), Get(totals, "", sc.paper, "rah", s));
      const std::string where = fmt::format("{} s{} d{}", sc.paper, sub, depth);
      const std::optional<Outcome> checks[] = {Within(rah, rah_pub, "{:.1f}"), Within(crsh, crsh_pub, "{:.1f}"),
                                                Within(ratio, ratio_pub, "{:.3f}")};
      relations.push_back({kFaithfulTotal, where + " RAH", checks[0], std::nullopt});
      relations.push_back({kFaithfulTotal, where + " CRSH", checks[1], std::nullopt});
      relations.push_back({kFaithfulRatio, where, checks[2], std::nullopt});
      int held = 0, judged = 0;
      for (const auto& c : checks)
        if (c) held += c->holds, ++judged;
      t.rows.push_back({sc.paper, fmt::format("s{} d{}", sub, depth), Number(rah_pub, "{:.1f}"), Number(rah, "{:.1f}"),
                        Number(Quotient(rah, rah_pub), "{:.3f}"), Number(crsh_pub, "{:.1f}"), Number(crsh, "{:.1f}"),
                        Number(Quotient(crsh, crsh_pub), "{:.3f}"), Number(ratio_pub, "{:.3f}"), Number(ratio_default, "{:.3f}"),
                        Number(ratio, "{:.3f}"), fmt::format("{} of {} within 15 %", held, judged)});
    }
  return t;
}

}  // namespace rayspace::reproduce
