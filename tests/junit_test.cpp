// JUnit XML (rayspace/junit.h) and the reproduce report's relation checks as JUnit: counts, escaping,
// and every document valid under docs/schemas/junit.xsd (xmllint), which rejects a broken one.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "rayspace/junit.h"
#include "rayspace/reproduce/report.h"

namespace {

using rayspace::JUnitCase;
using rayspace::JUnitSuite;

// xmllint's verdict on `xml` under the schema: its exit code (0: valid).
int Validate(const std::string& xml, const std::string& name) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() / ("rayspace-junit-test-" + name + ".xml");
  std::ofstream(file) << xml;
  const std::string cmd = std::string(RAYSPACE_XMLLINT) + " --noout --schema " RAYSPACE_SOURCE_DIR "/docs/schemas/junit.xsd " +
                          file.string() + " 2>/dev/null";
  const int rc = std::system(cmd.c_str());
  std::filesystem::remove(file);
  return rc;
}

JUnitCase Case(std::string classname, std::string name, double seconds, JUnitCase::Outcome outcome = JUnitCase::Outcome::kPassed,
               std::string type = {}, std::string message = {}, std::string details = {}, std::string output = {}) {
  JUnitCase c;
  c.classname = std::move(classname);
  c.name = std::move(name);
  c.seconds = seconds;
  c.outcome = outcome;
  c.type = std::move(type);
  c.message = std::move(message);
  c.details = std::move(details);
  c.output = std::move(output);
  return c;
}

std::size_t Count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("junit: counts per suite and in all, one element per outcome, valid under the schema") {
  const JUnitCase pass = Case("diff.trim", "0004 trim.shadow", 0.25);
  const JUnitCase fail = Case("diff.reduce", "0012 reduce.L2", 1.5, JUnitCase::Outcome::kFailure, "divergence",
                              "pairs[21]: expected 27, actual 9", "details\nover lines");
  const JUnitCase error = Case("mutate.trim.comp", "trim.comp:46:24", 0, JUnitCase::Outcome::kError, "error", "glslc failed");
  const JUnitCase skip = Case("mutate.trim.comp", "trim.comp:50:1", 0, JUnitCase::Outcome::kSkipped, "", "equivalent: proved", "", "out");
  const std::string xml = rayspace::JUnitXml("t", {{"one", {pass, fail}}, {"two", {error, skip, pass}}});
  CHECK(xml.find("<testsuites name=\"t\" tests=\"5\" failures=\"1\" errors=\"1\" skipped=\"1\" time=\"2.000\">") != std::string::npos);
  CHECK(xml.find("<testsuite name=\"one\" tests=\"2\" failures=\"1\" errors=\"0\" skipped=\"0\" time=\"1.750\">") != std::string::npos);
  CHECK(xml.find("<testsuite name=\"two\" tests=\"3\" failures=\"0\" errors=\"1\" skipped=\"1\" time=\"0.250\">") != std::string::npos);
  CHECK(Count(xml, "<testcase ") == 5);
  CHECK(Count(xml, "<failure ") == 1);
  CHECK(Count(xml, "<error ") == 1);
  CHECK(Count(xml, "<skipped ") == 1);
  CHECK(xml.find("message=\"pairs[21]: expected 27, actual 9\">details&#10;over lines</failure>") != std::string::npos);
  CHECK(Validate(xml, "counts") == 0);
  // The schema can say no: a suite without its failure count.
  std::string broken = xml;
  broken.erase(broken.find(" failures=\"1\" errors=\"0\""), 13);
  CHECK(Validate(broken, "broken") != 0);
  CHECK(Validate(rayspace::JUnitXml("empty", {}), "empty") == 0);
}

TEST_CASE("junit: markup, control characters and invalid UTF-8 in names and messages stay well-formed") {
  const JUnitCase c = Case("a<b>&\"c'", std::string("nul\0bell\x07", 9) + " \xC3\xA9 \xFF\xFE end", -1.0, JUnitCase::Outcome::kFailure,
                           "t", "\xE2\x82", "</failure><x>");
  const std::string xml = rayspace::JUnitXml("n", {{"s", {c}}});
  CHECK(xml.find("classname=\"a&lt;b&gt;&amp;&quot;c&apos;\"") != std::string::npos);
  CHECK(xml.find("nul\xEF\xBF\xBD" "bell\xEF\xBF\xBD \xC3\xA9 \xEF\xBF\xBD\xEF\xBF\xBD end") != std::string::npos);  // é kept
  CHECK(xml.find("&lt;/failure&gt;&lt;x&gt;</failure>") != std::string::npos);
  CHECK(xml.find("time=\"0.000\"") != std::string::npos);  // a negative time is written as 0
  CHECK(Validate(xml, "escape") == 0);
}

TEST_CASE("junit: reproduce's relation checks, a case per relation and place, failed where ours does not hold") {
  rayspace::reproduce::Report report;
  report.relations.push_back({"CRSH total < RAH total", "table 4.1, s8 d2", rayspace::reproduce::Outcome{true, "1 < 2"},
                              rayspace::reproduce::Outcome{true, "3 < 4"}});
  report.relations.push_back({"total < brute force", "table 4.2", rayspace::reproduce::Outcome{false, "9 < 5"}, std::nullopt});
  report.relations.push_back({"total < brute force", "table 4.3", std::nullopt, rayspace::reproduce::Outcome{true, "1 < 2"}});
  const std::string xml = rayspace::reproduce::ReportJUnit(report);
  CHECK(xml.find("tests=\"3\" failures=\"1\" errors=\"0\" skipped=\"1\"") != std::string::npos);
  CHECK(xml.find("message=\"total &lt; brute force fails on ours: 9 &lt; 5\"") != std::string::npos);
  CHECK(Validate(xml, "reproduce") == 0);
}
