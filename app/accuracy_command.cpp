#include "accuracy_command.h"
#include "rayspace/frame/command_util.h"

#include <filesystem>
#include <system_error>

#include "rayspace/accuracy/measure.h"
#include "rayspace/accuracy/report.h"
#include "rayspace/accuracy/sampler.h"
#include "rayspace/accuracy/grid.h"
#include "rayspace/accuracy/tl.h"
#include "rayspace/frame/memory_estimate.h"
#include "rayspace/plot.h"
#include "rayspace/error.h"
#include "rayspace/output_file.h"
#include "rayspace/scene.h"

namespace rayspace::app {

ExitCode RunAccuracy(const AccuracyArgs& args) {
  emu::FrameOptions fo;
  const Scene scene = LoadSceneForFrame(args.scene, args.data, args.size, fo.width, fo.height);
  // Its end-to-end frames run one after another, each beside the exact one it is compared with.
  CheckFitsMachine(EstimateFrameMemory(scene, fo.width, fo.height, {.copies = 2}), fo.width, fo.height, "--size",
                   "the accuracy run");
  if (args.samples < 100 || args.samples > 10000000) ThrowInput("--samples {}: expected 100 to 10000000", args.samples);
  if (!(args.min_time >= 0.001 && args.min_time <= 60)) ThrowInput("--min-time {}: expected 0.001 to 60 seconds", args.min_time);
  plot::CheckTool();  // before the measurements, not after them
  MakeOutputDirectory(args.out, "--out");
  accuracy::ReportFiles files = accuracy::OpenReportFiles(args.out, scene);
  const SceneBuffers b = FlattenScene(scene);

  // 1. The workload: queries sampled from a CRSH frame, and near-boundary variants of them.
  const accuracy::Workload workload = accuracy::SampleWorkload(scene, b, fo, args.samples);
  accuracy::Report report;
  report.scene = scene.name;
  report.width = fo.width;
  report.height = fo.height;
  report.workload = &workload;
  // 2. Cone-sphere modes, 3. ray-triangle modes, each against the exact answer.
  accuracy::MeasureConeModes(workload, report.rows, args.min_time);
  accuracy::MeasureTriModes(workload, report.rows, args.min_time);
  const accuracy::SphereWorkload spheres = accuracy::SampleSpheres(scene, b, fo, args.samples);
  report.spheres = &spheres;
  accuracy::MeasureSphereModes(spheres, report.rows, args.min_time);
  // 4. End to end: the frame with each mode in the traversal or the final tests, against the exact one.
  if (args.end_to_end) {
    report.cone_e2e = accuracy::ConeEndToEnd(scene, b, fo);
    report.tri_e2e = accuracy::TriEndToEnd(scene, b, fo);
    report.sphere_e2e = accuracy::SphereEndToEnd(scene, b, fo);
    report.grid_e2e = accuracy::GridEndToEnd(scene, b, fo);
  }
  // 5. Report: markdown, CSV, plot.
  accuracy::WriteReport(files, report);
  return ExitCode::kOk;
}

}  // namespace rayspace::app
