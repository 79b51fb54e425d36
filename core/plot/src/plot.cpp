#include "rayspace/plot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <regex>

#include <fmt/format.h>

#include "gnuplot_process.h"
#include "rayspace/error.h"

namespace rayspace::plot {
namespace {

// A gnuplot single-quoted string: no escapes but '' for a quote; a line break would end the command.
std::string Quote(const Plot& plot, const std::string& text) {
  if (text.find_first_of("\n\r") != std::string::npos) ThrowInput("plot '{}': the text '{}' has a line break", plot.title, text);
  std::string q = "'";
  for (char c : text) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

// A number exactly as written back (17 significant digits), refused when it cannot be drawn.
std::string Number(const Plot& plot, const Axis& axis, const char* name, double v) {
  if (!std::isfinite(v)) ThrowInput("plot '{}': {} value {} is not finite", plot.title, name, v);
  if (axis.scale == Scale::kLog && v <= 0)
    ThrowInput("plot '{}': {} value {} on the log {} axis '{}': a log axis needs values above 0", plot.title, name, v, name, axis.label);
  return fmt::format("{:.17g}", v);
}

// An axis whose data all share one value and that has no range of its own gets one around that value
// (a factor of 2 each way on a log axis, 1 each way on a linear one): gnuplot would warn of an empty
// range, and a plot of one configuration (`--only`) is a plot all the same.
Axis WithExtent(const Plot& plot, Axis axis, double Point::*coordinate) {
  if (axis.min || axis.max) return axis;
  std::optional<double> lo, hi;
  for (const Series& series : plot.series)
    for (const Point& p : series.points) {
      lo = std::min(lo.value_or(p.*coordinate), p.*coordinate);
      hi = std::max(hi.value_or(p.*coordinate), p.*coordinate);
    }
  if (!lo || *lo != *hi || !std::isfinite(*lo)) return axis;
  if (axis.scale == Scale::kLog) {
    if (*lo <= 0) return axis;  // refused where the data are written
    axis.min = *lo / 2, axis.max = *lo * 2;
  } else {
    axis.min = *lo - 1, axis.max = *lo + 1;
  }
  return axis;
}

void AxisLines(const Plot& plot, const Axis& axis, const char* name, std::string& s) {
  s += fmt::format("set {}label {}\n", name, Quote(plot, axis.label));
  if (axis.scale == Scale::kLog) s += fmt::format("set logscale {} 10\nset format {} '1e%T'\n", name, name);
  if (axis.min || axis.max)
    s += fmt::format("set {}range [{}:{}]\n", name, axis.min ? Number(plot, axis, name, *axis.min) : "*",
                     axis.max ? Number(plot, axis, name, *axis.max) : "*");
  if (axis.ticks.empty()) return;
  std::string ticks;
  for (const Tick& t : axis.ticks) ticks += fmt::format("{}{} {}", ticks.empty() ? "" : ", ", Quote(plot, t.label), Number(plot, axis, name, t.value));
  s += fmt::format("set {}tics ({})\n", name, ticks);
}

// The series' data block: x y "label" per line. Labels are double-quoted data fields, which cannot
// hold a double quote.
std::string DataBlock(const Plot& plot, const Series& series, std::size_t index) {
  std::string s = fmt::format("$d{} << EOD\n", index);
  for (const Point& p : series.points) {
    if (p.label.find_first_of("\"\n\r") != std::string::npos)
      ThrowInput("plot '{}': point label '{}' of series '{}' has a double quote or a line break", plot.title, p.label, series.title);
    s += fmt::format("{} {} \"{}\"\n", Number(plot, plot.x, "x", p.x), Number(plot, plot.y, "y", p.y), p.label);
  }
  return s + "EOD\n";
}

std::string SeriesClause(const Plot& plot, const Series& series, std::size_t index) {
  static const std::regex colour("#[0-9a-fA-F]{6}");
  if (!std::regex_match(series.colour, colour))
    ThrowInput("plot '{}': series '{}' has colour '{}', not #rrggbb", plot.title, series.title, series.colour);
  const char* with = series.style == Style::kPoints ? "points" : series.style == Style::kLines ? "lines" : "linespoints";
  // Lines take no point type: gnuplot refuses one there.
  const std::string marker = series.style == Style::kLines ? "" : fmt::format(" pt {} ps 1.2", static_cast<int>(series.marker));
  const std::string look = fmt::format("with {}{} lw 1.5 lc rgb '{}'", with, marker, series.colour);
  const std::string title = series.title.empty() ? "notitle" : "title " + Quote(plot, series.title);
  if (series.points.empty()) return fmt::format("keyentry {} {}", series.marker == Marker::kNone ? "with points pt -1 ps 0" : look, title);
  const std::string labels = fmt::format("$d{} using 1:2:3 with labels offset char 0.8,0.5 left notitle", index);
  // A series of labels alone (MergeCloseLabels): no marker of its own.
  if (series.marker == Marker::kNone && series.style == Style::kPoints) return labels;
  std::string clause = fmt::format("$d{} using 1:2 {} {}", index, look, title);
  for (const Point& p : series.points)
    if (!p.label.empty()) return clause + ", " + labels;
  return clause;
}

}  // namespace

namespace {

// A value's position along an axis, 0 at its minimum and 1 at its maximum (on a log axis, in
// decades); the data's extent where the axis has no range.
struct AxisMap {
  bool log = false;
  double lo = 0, span = 1;
  AxisMap(const Axis& a, double data_lo, double data_hi) : log(a.scale == Scale::kLog) {
    const double from = a.min.value_or(data_lo), to = a.max.value_or(data_hi);
    lo = At(from);
    span = std::max(At(to) - lo, 1e-300);
  }
  double At(double v) const { return log ? std::log10(v) : v; }
  double operator()(double v) const { return (At(v) - lo) / span; }
};

bool LabelLess(const std::string& a, const std::string& b) {
  const auto number = [](const std::string& s) { return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos && s.size() < 19; };
  if (number(a) && number(b)) return std::stoull(a) < std::stoull(b);
  return a < b;
}

}  // namespace

void MergeCloseLabels(Plot& plot, double reach) {
  struct Labelled {
    double x, y;  // the point's own coordinates
    double fx, fy;  // as fractions of the axes
    std::string label;
  };
  std::vector<Labelled> all;
  double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
  for (const Series& s : plot.series)
    for (const Point& p : s.points) xlo = std::min(xlo, p.x), xhi = std::max(xhi, p.x), ylo = std::min(ylo, p.y), yhi = std::max(yhi, p.y);
  const AxisMap mx(plot.x, xlo, xhi), my(plot.y, ylo, yhi);
  for (Series& s : plot.series)
    for (Point& p : s.points)
      if (!p.label.empty()) {
        all.push_back({p.x, p.y, mx(p.x), my(p.y), p.label});
        p.label.clear();
      }
  std::stable_sort(all.begin(), all.end(), [](const Labelled& a, const Labelled& b) { return a.fx < b.fx; });
  struct Cluster {
    double x, y, fx, fy, last_fx;
    std::vector<std::string> labels;
    std::size_t chars = 0;  // of the joined label
  };
  // A label's text runs right of its point: about 7 pixels a character over a plot area of about
  // half the image's width (the key sits outside, right), as a fraction of the x axis.
  const double char_width = 7.0 / (0.5 * std::max(plot.width, 16));
  std::vector<Cluster> clusters;
  for (const Labelled& l : all) {
    const auto near = std::find_if(clusters.begin(), clusters.end(), [&](const Cluster& c) {
      return std::abs(c.fy - l.fy) < reach && (l.fx - c.last_fx < reach || l.fx - c.fx < reach + c.chars * char_width);
    });
    if (near == clusters.end()) {
      clusters.push_back({l.x, l.y, l.fx, l.fy, l.fx, {l.label}, l.label.size()});
      continue;
    }
    near->last_fx = l.fx;
    if (std::find(near->labels.begin(), near->labels.end(), l.label) == near->labels.end()) {
      near->labels.push_back(l.label);
      near->chars += 1 + l.label.size();
    }
  }
  Series labels{"", Style::kPoints, Marker::kNone, "#000000", {}};
  for (Cluster& c : clusters) {
    std::sort(c.labels.begin(), c.labels.end(), LabelLess);
    std::string text;
    for (const std::string& l : c.labels) text += (text.empty() ? "" : ",") + l;
    labels.points.push_back({c.x, c.y, text});
  }
  if (!labels.points.empty()) plot.series.push_back(std::move(labels));
}

std::string Script(const Plot& plot, Format format) {
  if (plot.width < 16 || plot.height < 16) ThrowInput("plot '{}': size {}x{} is too small", plot.title, plot.width, plot.height);
  // noenhanced: labels are drawn as written (no ^, _, @ or {} markup).
  std::string s = format == Format::kSvg
                      ? fmt::format("set terminal svg size {},{} noenhanced font 'DejaVu Sans,12' background '#ffffff'\n", plot.width, plot.height)
                      : fmt::format("set terminal pngcairo size {},{} noenhanced font 'DejaVu Sans,10' background '#ffffff'\n", plot.width, plot.height);
  s += "set encoding utf8\nset output\n";
  s += fmt::format("set title {}\n", Quote(plot, plot.title));
  AxisLines(plot, WithExtent(plot, plot.x, &Point::x), "x", s);
  AxisLines(plot, WithExtent(plot, plot.y, &Point::y), "y", s);
  s += "set grid\nset key outside right top Left reverse noautotitle\n";
  std::string clauses;
  for (std::size_t i = 0; i < plot.series.size(); ++i) {
    if (!plot.series[i].points.empty()) s += DataBlock(plot, plot.series[i], i);
    clauses += (clauses.empty() ? "" : ", \\\n     ") + SeriesClause(plot, plot.series[i], i);
  }
  if (clauses.empty()) ThrowInput("plot '{}': no series", plot.title);
  return s + "plot " + clauses + "\n";
}

void CheckTool() {
  if (!OnPath("gnuplot")) ThrowInput("gnuplot not found: install gnuplot-nox");
}

std::vector<std::uint8_t> Render(const Plot& plot, Format format) {
  const std::string script = Script(plot, format);
  CheckTool();
  const ProcessResult r = RunProcess({"gnuplot"}, script);
  if (!r.started) ThrowInput("gnuplot not found: install gnuplot-nox");
  // gnuplot's message on one line: whitespace runs (its indentation, line breaks) as single spaces.
  std::string err;
  for (char c : r.err)
    if (!std::isspace(static_cast<unsigned char>(c))) err += c;
    else if (!err.empty() && err.back() != ' ') err += ' ';
  if (!err.empty() && err.back() == ' ') err.pop_back();
  if (r.exit_code != 0 || !err.empty())
    ThrowInput("plot '{}': gnuplot {}{}{}", plot.title, r.exit_code == 0 ? "wrote to stderr" : fmt::format("exited with {}", r.exit_code),
               err.empty() ? "" : ": ", err);
  if (r.out.empty()) ThrowInput("plot '{}': gnuplot drew nothing", plot.title);
  return {r.out.begin(), r.out.end()};
}

}  // namespace rayspace::plot
