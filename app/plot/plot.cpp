#include "plot.h"

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
  std::string clause = fmt::format("$d{} using 1:2 {} {}", index, look, title);
  for (const Point& p : series.points)
    if (!p.label.empty()) return clause + fmt::format(", $d{} using 1:2:3 with labels offset char 0.8,0.5 left notitle", index);
  return clause;
}

}  // namespace

std::string Script(const Plot& plot, Format format) {
  if (plot.width < 16 || plot.height < 16) ThrowInput("plot '{}': size {}x{} is too small", plot.title, plot.width, plot.height);
  // noenhanced: labels are drawn as written (no ^, _, @ or {} markup).
  std::string s = format == Format::kSvg
                      ? fmt::format("set terminal svg size {},{} noenhanced font 'DejaVu Sans,12' background '#ffffff'\n", plot.width, plot.height)
                      : fmt::format("set terminal pngcairo size {},{} noenhanced font 'DejaVu Sans,10' background '#ffffff'\n", plot.width, plot.height);
  s += "set encoding utf8\nset output\n";
  s += fmt::format("set title {}\n", Quote(plot, plot.title));
  AxisLines(plot, plot.x, "x", s);
  AxisLines(plot, plot.y, "y", s);
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
