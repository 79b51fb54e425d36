// The report's sections on the thesis's fit (docs/reproduce.md, "Fits"): the fitted camera and light
// with the fit set's residuals, how the objective moves with each parameter, and the targets judged
// out of sample on SPONZA's other numbers.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/reproduce/published.h"
#include "rayspace/reproduce/report.h"

namespace rayspace::reproduce {

// The project relation that checks a run's frame of the fitted scene against the committed record.
inline constexpr const char* kFitMatches = "the fitted scene renders the fit's counts";

// A protocol's committed fit record (reproduce/fits/thesis-sponza.json, thesis-sponza-2.json; carried
// in the binary); null when none is committed.
const nlohmann::json& ThesisSponzaFit(int protocol);

// The fitted values and the residuals of the fit set. `rah` is this run's SPONZA RAH s8 d2 (slot
// counts), or null: when it is there, a project relation checks that it gives the record's counts
// (the committed fit is the scene's).
Table FitTable(const nlohmann::json& record, const Result* rah, std::vector<RelationRow>& relations);
// Every committed protocol's fitted point on the fit set, side by side.
Table FitsTable();
// J and the fit set's counts with each parameter moved by -1/8 .. +1/8 of its range.
Table SensitivityTable(const nlohmann::json& record);
// SPONZA's totals, CRSH/RAH ratios and per-level cells within 15 % of the thesis's, in sample (RAH s8
// d2, the fit set) and out of sample; `results` in slot counts.
Table SponzaTargetsTable(const std::vector<Result>& results, const Published& published);
// reproduce thesis-ablation: per variant (AblationSwitches), the same scores out of sample and the
// per-level cells gained or lost against rayspace's defaults; `results` in slot counts.
Table AblationTable(const std::vector<Result>& results, const Published& published);
// reproduce thesis-ablation: every committed fit's scene out of sample, under the defaults and the
// last variant; empty with one fit.
Table AblationFitsTable(const std::vector<Result>& results, const Published& published);

}  // namespace rayspace::reproduce
