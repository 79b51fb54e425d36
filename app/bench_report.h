// What `rayspace bench` prints and writes: the table, the time growth with pixels, the digest check
// and the JSON file.
#pragma once
#include <cstdio>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "bench_run.h"

namespace rayspace::app {

// The table (one row per scene, size and configuration) and its notes.
void PrintBenchTable(std::FILE* out, const std::vector<BenchRow>& rows, int repetitions);
// Per scene and configuration, how the median frame time grows from each size to the next.
void PrintGrowthTable(std::FILE* out, const std::vector<BenchRow>& rows);

// Configurations of one --algo (and every repetition of one) must give the same digest for the same
// scene and size. Prints one error line on `err` per disagreement and a line on `out` naming what
// agreed; false when something disagreed.
bool CheckDigests(std::FILE* out, std::FILE* err, const std::vector<BenchRow>& rows);

nlohmann::json BenchJson(const std::vector<BenchRow>& rows, int repetitions, int threads);

}  // namespace rayspace::app
