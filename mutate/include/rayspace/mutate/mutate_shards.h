// `rayspace mutate --shard I/N` and `mutate merge`: shard I runs the chosen mutants and variants I,
// I+N, ...; merge puts the N reports together into the report one run writes, byte for byte. For that
// the report holds nothing a run decides by itself: no times, no temporary paths, no command line.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace rayspace::app::mutate_shards {

// The scores of a list of mutant verdicts: per file and in all (killed, survived, equivalent,
// stillborn, invalid, unexplained survivors, killed / (killed + survived)).
nlohmann::json Summaries(const std::vector<nlohmann::json>& mutants);

// The mutants run on both sides whose verdicts differ (killed on one, survived on the other).
nlohmann::json Differences(const std::vector<nlohmann::json>& first, const std::vector<nlohmann::json>& second,
                           const std::string& a, const std::string& b);

// The report as a pure function of the run's choices: every "seconds" member removed, and `work` (the
// run's working directory) in any string replaced by "<work>".
void MakeDeterministic(nlohmann::json& report, const std::string& work);

// The N shard reports (name, report) of one run merged into the run's report. Throws InputError
// naming the file when one is not a shard report, when they are not all shards of one run (any
// member but the shard's own results differs), or when a shard is missing or given twice.
nlohmann::json Merge(const std::vector<std::pair<std::string, nlohmann::json>>& shards);

}  // namespace rayspace::app::mutate_shards
