// The report's comparison of `--faithful thesis` with the thesis: per scene and hierarchy shape, the
// RAH and CRSH tests per traced ray and their ratio CRSH/RAH, published, ours with rayspace's defaults, and ours with
// the thesis's method as printed; the target is each within 15 % of the published.
#pragma once
#include <vector>

#include "rayspace/reproduce/report.h"

namespace rayspace::reproduce {

inline constexpr const char* kFaithfulTotal = "faithful tests per ray within 15 % of the thesis's";
inline constexpr const char* kFaithfulRatio = "faithful CRSH/RAH within 15 % of the thesis's";
// The tolerance of both relations: |ours / published - 1| <= 0.15.
inline constexpr double kFaithfulTolerance = 0.15;

// The table, and its relations appended to `relations` (ours only: the published side is the
// reference, so it has no verdict).
Table FaithfulTable(const std::vector<Result>& results, const Published& published, std::vector<RelationRow>& relations);

}  // namespace rayspace::reproduce
