// A report table's plot: ours against published on log axes, one point per row that has both numbers,
// with the line ours = published, so a reader sees at a glance which rows are off and by how much.
#include <algorithm>
#include <cstdlib>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "rayspace/plot.h"
#include "rayspace/reproduce/report.h"

namespace rayspace::reproduce {
namespace {

std::optional<std::size_t> ColumnIndex(const Table& t, const std::string& name) {
  const auto it = std::find(t.columns.begin(), t.columns.end(), name);
  if (it == t.columns.end()) return std::nullopt;
  return static_cast<std::size_t>(it - t.columns.begin());
}

// A cell as a positive number; none for text, blanks and zeros (a log axis cannot show them).
std::optional<double> Positive(const std::string& cell) {
  std::string digits;
  for (char c : cell)
    if (c != ',' && c != '%') digits += c;
  if (digits.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(digits.c_str(), &end);
  if (end != digits.c_str() + digits.size() || !(v > 0)) return std::nullopt;
  return v;
}

const plot::Marker kMarkers[] = {plot::Marker::kFilledCircle, plot::Marker::kOpenSquare, plot::Marker::kFilledTriangle,
                                 plot::Marker::kOpenCircle};
const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};

// One series per value of the table's first column (the algorithm), points labelled by row number.
std::vector<plot::Series> RowSeries(const Table& t, std::size_t pub, std::size_t ours, double& lo, double& hi) {
  std::map<std::string, plot::Series> by_group;
  std::vector<std::string> order;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const std::vector<std::string>& row = t.rows[i];
    const std::optional<double> x = Positive(row.at(pub)), y = Positive(row.at(ours));
    if (!x || !y) continue;
    const std::string group = row.at(ColumnIndex(t, "algorithm").value_or(0));
    if (!by_group.count(group)) {
      const std::size_t k = order.size() % 4;
      by_group[group] = {group, plot::Style::kPoints, kMarkers[k], kColours[k], {}};
      order.push_back(group);
    }
    by_group[group].points.push_back({*x, *y, std::to_string(i + 1)});
    lo = std::min({lo, *x, *y});
    hi = std::max({hi, *x, *y});
  }
  std::vector<plot::Series> series;
  for (const std::string& g : order) series.push_back(std::move(by_group[g]));
  return series;
}

}  // namespace

std::string TablePlots(const Table& table, const std::filesystem::path& out) {
  // A totals table compares shares of brute force, which do not depend on the frame's size as counts do.
  std::optional<std::size_t> pub = ColumnIndex(table, "published % of brute force"), ours = ColumnIndex(table, "ours % of brute force");
  std::string quantity = "% of brute force";
  if (!pub || !ours) {
    pub = ColumnIndex(table, "published"), ours = ColumnIndex(table, "ours");
    quantity = "tests";
  }
  // Switch tables (Toczek et al.'s table 1): each row over the row with every switch off.
  if (!pub || !ours) {
    pub = ColumnIndex(table, "published x all off"), ours = ColumnIndex(table, "ours x all off");
    quantity = "nodes per ray over every switch off";
  }
  if (!pub || !ours) return {};
  double lo = 1e300, hi = 0;
  std::vector<plot::Series> series = RowSeries(table, *pub, *ours, lo, hi);
  if (series.empty()) return {};
  plot::Plot p;
  p.title = table.title;
  p.x = {"published, " + quantity, plot::Scale::kLog, lo / 2, hi * 2, {}};
  p.y = {"ours, " + quantity, plot::Scale::kLog, lo / 2, hi * 2, {}};
  p.series.push_back({"ours = published", plot::Style::kLines, plot::Marker::kNone, "#808080", {{lo / 2, lo / 2, ""}, {hi * 2, hi * 2, ""}}});
  for (plot::Series& s : series) p.series.push_back(std::move(s));
  const std::vector<std::uint8_t> svg = plot::Render(p, plot::Format::kSvg);
  const std::string name = "table-" + table.id + ".svg";
  std::filesystem::create_directories(out / "plots");
  WriteText(out / "plots" / name, std::string(svg.begin(), svg.end()), "a report plot");
  return fmt::format("Plot: [plots/{}](plots/{}) (ours against published, log axes; points labelled by row).", name, name);
}

}  // namespace rayspace::reproduce
