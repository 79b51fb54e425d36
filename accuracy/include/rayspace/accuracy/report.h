// `rayspace accuracy`, the report: a markdown table, CSV and a log-log plot of error rate against
// time per test.
#pragma once
#include <string>
#include <vector>

#include "rayspace/accuracy/measure.h"
#include "rayspace/accuracy/sampler.h"
#include "rayspace/accuracy/tl.h"
#include "rayspace/output_file.h"
#include "rayspace/scene.h"

namespace rayspace::accuracy {

struct Report {
  std::string scene;   // the scene's name
  int width = 0, height = 0;
  const Workload* workload = nullptr;
  std::vector<Row> rows;
  const SphereWorkload* spheres = nullptr;      // the traversal lists' sphere tests
  std::vector<EndToEnd> cone_e2e, tri_e2e, sphere_e2e, grid_e2e;  // empty: not measured
};

// DIR/<scene>-accuracy.{md,csv,svg,png}, opened (and so checked) before the measurements.
struct ReportFiles {
  std::string base;  // DIR/<scene>-accuracy
  OutputFile md, csv, svg, png;
};
ReportFiles OpenReportFiles(const std::string& dir, const Scene& scene);

// Writes the four files and prints the markdown and the files written.
void WriteReport(ReportFiles& files, const Report& report);

}  // namespace rayspace::accuracy
