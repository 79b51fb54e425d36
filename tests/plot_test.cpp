// The gnuplot plots: script text, refusals, and rendered images that are the same bytes every time.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "rayspace/plot.h"
#include "rayspace/error.h"

namespace {

using namespace rayspace::plot;

Plot Sample() {
  Plot p;
  p.title = "it's a \"test\"";
  p.x = {"ns per test", Scale::kLog, 1.0, 1e6, {}};
  p.y = {"rate", Scale::kLinear, std::nullopt, std::nullopt, {{0.5, "half"}}};
  p.series.push_back({"filled", Style::kPoints, Marker::kFilledSquare, "#d91a1a", {{10, 0.25, "1"}, {1000, 0.75, "2"}}});
  p.series.push_back({"line", Style::kLines, Marker::kNone, "#1a59d9", {{1, 0.1, ""}, {1e5, 0.9, ""}}});
  p.series.push_back({"a note", Style::kPoints, Marker::kNone, "#000000", {}});
  return p;
}

// Every element opened is closed, in order (enough to catch a truncated or interleaved SVG).
bool BalancedXml(const std::string& s) {
  std::vector<std::string> open;
  for (std::size_t at = s.find('<'); at != std::string::npos; at = s.find('<', at + 1)) {
    const std::size_t end = s.find('>', at);
    if (end == std::string::npos) return false;
    const std::string tag = s.substr(at + 1, end - at - 1);
    if (tag.empty() || tag[0] == '?' || tag[0] == '!' || tag.back() == '/') continue;
    const std::string name = tag.substr(tag[0] == '/' ? 1 : 0, tag.find_first_of(" \n\t") - (tag[0] == '/' ? 1 : 0));
    if (tag[0] != '/') open.push_back(name);
    else if (open.empty() || open.back() != name) return false;
    else open.pop_back();
  }
  return open.empty();
}

// PATH for the life of the object.
struct PathOverride {
  std::string old = std::getenv("PATH") ? std::getenv("PATH") : "";
  explicit PathOverride(const std::string& path) { ::setenv("PATH", path.c_str(), 1); }
  ~PathOverride() { ::setenv("PATH", old.c_str(), 1); }
};

}  // namespace

TEST_CASE("plot: labels are single-quoted with quotes doubled, data inline") {
  const std::string s = Script(Sample(), Format::kSvg);
  CHECK(s.find("set title 'it''s a \"test\"'\n") != std::string::npos);
  CHECK(s.find("set logscale x 10\n") != std::string::npos);
  CHECK(s.find("set xrange [1:1000000]\n") != std::string::npos);
  CHECK(s.find("set ytics ('half' 0.5)\n") != std::string::npos);
  CHECK(s.find("$d0 << EOD\n10 0.25 \"1\"\n1000 0.75 \"2\"\nEOD\n") != std::string::npos);
  CHECK(s.find("$d0 using 1:2:3 with labels") != std::string::npos);
  CHECK(s.find("keyentry with points pt -1 ps 0 title 'a note'") != std::string::npos);
  CHECK(s.find("noenhanced") != std::string::npos);
}

TEST_CASE("plot: values and text it cannot draw are refused naming the plot") {
  Plot p = Sample();
  SUBCASE("zero on a log axis") {
    p.series[0].points[0].x = 0;
    CHECK_THROWS_WITH_AS(Script(p, Format::kSvg),
                         "plot 'it's a \"test\"': x value 0 on the log x axis 'ns per test': a log axis needs values above 0",
                         rayspace::InputError);
  }
  SUBCASE("negative log range") {
    p.x.min = -1;
    CHECK_THROWS_AS(Script(p, Format::kSvg), rayspace::InputError);
  }
  SUBCASE("not finite") {
    p.series[1].points[0].y = std::nan("");
    CHECK_THROWS_WITH_AS(Script(p, Format::kSvg), "plot 'it's a \"test\"': y value nan is not finite", rayspace::InputError);
  }
  SUBCASE("line break in a label") {
    p.y.label = "two\nlines";
    CHECK_THROWS_AS(Script(p, Format::kSvg), rayspace::InputError);
  }
  SUBCASE("double quote in a point label") {
    p.series[0].points[0].label = "\"";
    CHECK_THROWS_AS(Script(p, Format::kSvg), rayspace::InputError);
  }
  SUBCASE("bad colour") {
    p.series[0].colour = "red";
    CHECK_THROWS_AS(Script(p, Format::kSvg), rayspace::InputError);
  }
}

TEST_CASE("plot: gnuplot renders a well-formed SVG and a PNG, the same bytes each time") {
  Plot p = Sample();
  p.y.label = "rate < 1 & more";  // XML's special characters, escaped by gnuplot
  const std::vector<std::uint8_t> a = Render(p, Format::kSvg), b = Render(p, Format::kSvg);
  const std::string svg(a.begin(), a.end());
  CHECK(svg.rfind("<?xml", 0) == 0);
  CHECK(svg.find("</svg>") != std::string::npos);
  CHECK(BalancedXml(svg));
  CHECK(svg.find("it's a \"test\"") != std::string::npos);
  CHECK(svg.find("rate &lt; 1 &amp; more") != std::string::npos);
  CHECK(svg.find("ns per test") != std::string::npos);
  CHECK(a == b);
  const std::vector<std::uint8_t> p1 = Render(Sample(), Format::kPng), p2 = Render(Sample(), Format::kPng);
  REQUIRE(p1.size() > 8);
  CHECK(std::string(p1.begin() + 1, p1.begin() + 4) == "PNG");
  CHECK(p1 == p2);
}

TEST_CASE("plot: one point, or points on one value, get a range around it and render without a warning") {
  Plot p;
  p.title = "one configuration";
  p.x = {"triangles", Scale::kLog, std::nullopt, std::nullopt, {}};
  p.y = {"tests", Scale::kLinear, std::nullopt, std::nullopt, {}};
  p.series.push_back({"ours", Style::kLinesPoints, Marker::kFilledCircle, "#d91a1a", {{948, 5, "1"}}});
  const std::string s = Script(p, Format::kSvg);
  CHECK(s.find("set xrange [474:1896]\n") != std::string::npos);
  CHECK(s.find("set yrange [4:6]\n") != std::string::npos);
  CHECK(Render(p, Format::kSvg).size() > 100);  // gnuplot's "empty x range" warning would be an error
  p.series.front().points.push_back({2000, 5, "2"});  // x spread: gnuplot's own range there
  const std::string two = Script(p, Format::kSvg);
  CHECK(two.find("set xrange") == std::string::npos);
  CHECK(two.find("set yrange [4:6]\n") != std::string::npos);
}

TEST_CASE("plot: gnuplot missing or failing is an error naming the plot") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rayspace_plot_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  SUBCASE("missing") {
    PathOverride path(dir.string());
    CHECK_THROWS_WITH_AS(CheckTool(), "gnuplot not found: install gnuplot-nox", rayspace::InputError);
    CHECK_THROWS_WITH_AS(Render(Sample(), Format::kSvg), "gnuplot not found: install gnuplot-nox", rayspace::InputError);
  }
  SUBCASE("failing") {
    {
      std::ofstream f(dir / "gnuplot");
      f << "#!/bin/sh\ncat >/dev/null\necho '         line 9: undefined variable: x' >&2\nexit 1\n";
    }
    std::filesystem::permissions(dir / "gnuplot", std::filesystem::perms::owner_all);
    PathOverride path(dir.string() + ":/usr/bin:/bin");
    CHECK_THROWS_WITH_AS(Render(Sample(), Format::kSvg),
                         "plot 'it's a \"test\"': gnuplot exited with 1: line 9: undefined variable: x", rayspace::InputError);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("plot: labels that would overlap are drawn once per cluster, joined in numeric order") {
  Plot p;
  p.title = "clusters";
  p.x = {"ns", Scale::kLog, 1.0, 1e6, {}};
  p.y = {"rate", Scale::kLog, 1e-7, 1.0, {}};
  // On the zero line: 10, 11 and 12 ns (a chain within reach), then 1000 ns alone; 10 ns again
  // higher up (another cluster), and a label repeated in one cluster.
  p.series.push_back({"a", Style::kPoints, Marker::kFilledSquare, "#d91a1a", {{10, 1e-7, "10"}, {12, 1e-7, "2"}, {1000, 1e-7, "3"}}});
  p.series.push_back({"b", Style::kPoints, Marker::kOpenSquare, "#1a59d9", {{11, 1e-7, "9"}, {10, 1e-2, "1"}, {11, 1e-7, "2"}}});
  MergeCloseLabels(p, 0.03);
  REQUIRE(p.series.size() == 3);
  for (std::size_t s = 0; s < 2; ++s) {
    CHECK(p.series[s].points.size() == 3);  // every point stays
    for (const Point& pt : p.series[s].points) CHECK(pt.label.empty());
  }
  const Series& labels = p.series[2];
  CHECK(labels.marker == Marker::kNone);
  CHECK(labels.title.empty());
  REQUIRE(labels.points.size() == 3);
  CHECK(labels.points[0].label == "2,9,10");  // numeric, not "10,2,9"; "2" once
  CHECK(labels.points[0].x == 10);
  CHECK(labels.points[0].y == 1e-7);
  CHECK(labels.points[1].label == "1");
  CHECK(labels.points[1].y == 1e-2);
  CHECK(labels.points[2].label == "3");
  // The labels' series draws labels only, and no point markers of its own.
  const std::string s = Script(p, Format::kSvg);
  CHECK(s.find("$d2 using 1:2:3 with labels") != std::string::npos);
  CHECK(s.find("$d2 using 1:2 with") == std::string::npos);
}
