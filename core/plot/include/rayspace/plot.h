// Plots drawn by gnuplot: a Plot value (title, axes, series) turned into a gnuplot script with its
// data inline and rendered by a gnuplot process into SVG or PNG bytes. The same Plot gives the same
// bytes on every run (no dates or random ids in gnuplot's output; tests/plot_test.cpp checks).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace rayspace::plot {

enum class Scale { kLinear, kLog };

// A tick at `value` labelled `label` (in place of gnuplot's numbers).
struct Tick {
  double value = 0;
  std::string label;
};

struct Axis {
  std::string label;
  Scale scale = Scale::kLinear;
  std::optional<double> min, max;  // the range; gnuplot's automatic range where unset
  std::vector<Tick> ticks;         // empty: gnuplot's
};

enum class Style { kPoints, kLines, kLinesPoints };
// gnuplot's point types, named by look.
enum class Marker { kFilledSquare = 5, kOpenSquare = 4, kFilledCircle = 7, kOpenCircle = 6, kFilledTriangle = 9, kOpenTriangle = 8, kNone = -1 };

struct Point {
  double x = 0, y = 0;
  std::string label;  // drawn beside the point when not empty
};

struct Series {
  std::string title;  // in the key; empty: not in the key
  Style style = Style::kPoints;
  Marker marker = Marker::kFilledCircle;
  std::string colour = "#000000";  // #rrggbb
  std::vector<Point> points;       // none: a key entry only (a note in the key)
};

struct Plot {
  std::string title;  // also names the plot in errors
  Axis x, y;
  std::vector<Series> series;
  int width = 900, height = 620;  // pixels
};

enum class Format { kSvg, kPng };

// Labels that would be drawn over each other are drawn once per cluster: points whose labels lie
// within `reach` of each other (a fraction of each axis's span, on the axis's scale), or under the
// text of a label to their left on the same line, share one label: the distinct labels joined by
// commas (numbers in numeric order), beside the cluster's leftmost point; the points keep their
// series and markers. A cluster grows from left to right, so a chain of close points is one cluster.
void MergeCloseLabels(Plot& plot, double reach);

// The gnuplot script for a plot, data inline; throws InputError naming the plot for values it
// cannot draw (a non-positive value on a log axis, a non-finite value, a bad colour).
std::string Script(const Plot& plot, Format format);

// The image gnuplot draws from Script(plot, format). Throws InputError naming the plot when gnuplot
// is missing, exits non-zero or writes anything on stderr.
std::vector<std::uint8_t> Render(const Plot& plot, Format format);

// Throws InputError "gnuplot not found: install gnuplot-nox" when no gnuplot is on PATH: call it
// before the work whose result is plotted.
void CheckTool();

}  // namespace rayspace::plot
