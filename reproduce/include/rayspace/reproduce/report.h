// The report of a `reproduce thesis` run, from its results alone (so that one run, a resumed run and
// merged shards write the same bytes): report.md with a section per thesis table, one CSV per table in
// tables/, results.json with every raw statistic; and, outside that byte-identical set, timings.md and
// timings.csv (phase times vary run to run).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "rayspace/reproduce/relations.h"
#include "rayspace/reproduce/store.h"

namespace rayspace::reproduce {

// One table of the report: its markdown section and its CSV.
struct Table {
  std::string id;     // names the CSV: tables/table-<id>.csv
  std::string title;  // the section's heading
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> notes;  // lines under the table: how the scene differs, the relations' verdicts
  // A series plot (Roger's figures): this column against that, one line per value of `plot_group`, log
  // axes; empty: the ours-against-published plot when the table has both columns.
  std::string plot_x, plot_y, plot_group;
};

// A relation checked on one table's numbers: its verdict on ours and on the published, and where the
// paper states it (section and words, or table); empty: a relation the project adds (an identity
// read off the tables, a target of its own), reported apart from the paper's.
struct RelationRow {
  std::string relation, where;
  std::optional<Outcome> ours, published;
  std::string source;
};

struct Report {
  std::string title = "CRSH thesis: published and ours";
  std::vector<Table> tables;
  std::vector<RelationRow> relations;
  std::vector<std::string> preamble;  // lines above the summary
};

// Builds every table from the results (any order) and the published numbers.
Report BuildReport(const std::vector<Result>& results, const Published& published);
// The published totals whose printed levels do not add up to them (the accounting identity), each
// with its terms, their sum and the printed totals it equals.
Table MisprintsTable(const Published& published);
// Appends the sections of `reproduce roger` (roger_report.cpp): a summary of its claims' verdicts, then a
// table per figure; each relation's verdict under its table and in the summary.
void AddRogerReport(Report& report, const std::vector<const Result*>& results);
// Figures 10 and 12 and the Museum's shadow rays (roger_reflectors.cpp), at the base frame width
// `side`; their claims are appended to `verdicts`. A table with no rows is left out.
std::vector<Table> RogerReflectorTables(const std::vector<const Result*>& results, int side,
                                        std::vector<std::vector<std::string>>& verdicts);
// The timings of `reproduce roger`: Roger's four phases per frame with the figure 9(a) claims judged,
// and time against cone-sphere tests (figures 13(b) and 13(c)). Not byte-identical.
std::vector<Table> RogerTimings(const std::vector<const Result*>& results);
// A table's series plot (plot_x against plot_y) into out/plots/table-<id>.svg, and its markdown line.
// `dir`: the folder under `out` (a plot of times goes apart from the reproducible ones).
std::string SeriesPlot(const Table& table, const std::filesystem::path& out, const std::string& dir = "plots");
std::string ReportMarkdown(const Report& report);
std::string TableCsv(const Table& table);
// The summary: per relation, how many of its checks hold, ours and published; `stated`: the
// relations the paper states (with their source), else those the project adds.
Table SummaryTable(const std::vector<RelationRow>& relations, bool stated = true);

// Writes report.md, tables/*.csv, results.json, timings.md and timings.csv into `out`, atomically each;
// returns the report.
Report WriteReport(const std::filesystem::path& out, const std::vector<Result>& results);
// The report's relation checks as JUnit XML (--junit): a test case per relation and place, passed
// when it holds on our numbers, failed with what was compared when it does not, skipped when ours has
// no verdict; the published side's verdict is the case's output.
std::string ReportJUnit(const Report& report);

// Draws the table's ours-against-published plot into out/plots/table-<id>.svg (gnuplot) and returns
// the markdown line that links it; nothing for a table without both columns.
std::string TablePlots(const Table& table, const std::filesystem::path& out);

}  // namespace rayspace::reproduce
