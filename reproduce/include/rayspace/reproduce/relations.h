// The relations the CRSH thesis states between its numbers, checked on the published numbers and on
// ours alike: each gives holds or fails with the numbers it compared.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rayspace/reproduce/counts.h"
#include "rayspace/reproduce/published.h"

namespace rayspace::reproduce {

// One algorithm's numbers in one configuration and scene, published or ours, in the thesis's terms.
struct Measurement {
  std::uint64_t total = 0, brute_force = 0;
  std::map<std::string, std::vector<LevelCounts>> levels;           // by SH/RE/RF, index L-1
  std::map<std::string, std::uint64_t> top_nodes_x_triangles;      // by SH/RE/RF
};

// A relation's verdict on one side: holds or fails, and what was compared ("469,683,524 < 170,116,000").
struct Outcome {
  bool holds = false;
  std::string detail;
};
std::string Verdict(const std::optional<Outcome>& o);  // "holds", "fails" or "n/a"

// The relations, each named as the report's summary names it.
inline constexpr const char* kCrshBelowRah = "CRSH total < RAH total";
// The thesis compares each configuration's CRSH total with its baseline's (subdivision 8, depth 2):
// above it on OFFICE and CORNELL, below it on SPONZA (sec. 4.4, "Configuration Comparison").
inline constexpr const char* kAboveBaseline = "CRSH total > the baseline's (s8 d2)";
inline constexpr const char* kBelowBaseline = "CRSH total < the baseline's (s8 d2)";
// And on SPONZA between depths: depth 4 below depth 3 at subdivision 8, above it at 16.
inline constexpr const char* kDeeperLowers = "CRSH depth 4 total < depth 3 total";
inline constexpr const char* kDeeperRaises = "CRSH depth 4 total > depth 3 total";
inline constexpr const char* kRahTopLevel = "RAH top level = top nodes x triangles";
inline constexpr const char* kIdentity = "total = sum of level intersections + level-1 hits x subdivision";
inline constexpr const char* kBelowBrute = "total < brute force";

Outcome CrshBelowRah(const Measurement& rah, const Measurement& crsh);
Outcome Below(const Measurement& m, const Measurement& reference);
Outcome Above(const Measurement& m, const Measurement& reference);
Outcome RahTopLevel(const Measurement& rah, int depth);
// Every level's intersections plus level 1's hits x subdivision (each hit's child slots tested).
std::uint64_t AccountedTotal(const Measurement& m, int subdivision);
Outcome Identity(const Measurement& m, int subdivision);
Outcome BelowBrute(const Measurement& m);

// The published numbers of one algorithm (RAH or CRSH) in one table, or nothing when the thesis prints
// no total for it. Top nodes come from the caption's ray counts (ThesisScene).
std::optional<Measurement> PublishedMeasurement(const Published& p, HierarchyShape s, const std::string& scene,
                                                const std::string& algorithm);
// Ours from a configuration's counts.
Measurement OurMeasurement(const Counts& c);

// 1234567 -> "1,234,567".
std::string Thousands(std::uint64_t v);

}  // namespace rayspace::reproduce
