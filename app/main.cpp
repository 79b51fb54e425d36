// rayspace command-line interface.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/output_checks.h"
#include "rayspace/error.h"
#include "rayspace/frame/version.h"
#include "rayspace/workgroup.h"
#include "accuracy_command.h"
#include "bench_command.h"
#include "shadow_bench.h"
#include "bench_configs.h"
#include "data_command.h"
#include "rayspace/exit_codes.h"
#include "ignored_options.h"
#include "rayspace/frame/render_command.h"
#include "simulate_command.h"
#include "rayspace/sim/device.h"
#include "render_options.h"
#include "rayspace/reproduce/command.h"
#include "reproduce_frame.h"
#ifdef RAYSPACE_HAVE_VULKAN
#include "devices_command.h"
#include "rayspace/diff/diff_command.h"
#include "rayspace/export/export_command.h"
#include "rayspace/mutate/mutate_command.h"
#include "rayspace/gpu/validation.h"
#include "frame_options.h"
#endif

namespace {

// Every command's arguments and its CLI11 subcommand (null when the build lacks it).
struct Commands {
  rayspace::app::RenderArgs render;
  rayspace::app::AccuracyArgs accuracy;
  rayspace::app::BenchArgs bench;
  rayspace::app::ShadowBenchArgs shadow_bench;
  CLI::App* shadow_bench_cmd = nullptr;
  rayspace::reproduce::ReproduceArgs reproduce;
  std::pair<CLI::App*, CLI::App*> reproduce_cmds{};
  rayspace::app::DataCheckArgs data_check;
  CLI::App* data_check_cmd = nullptr;
  rayspace::app::SimulateArgs simulate;
  CLI::App* simulate_cmd = nullptr;
  CLI::App *render_cmd = nullptr, *accuracy_cmd = nullptr, *bench_cmd = nullptr, *diff_cmd = nullptr, *replay_cmd = nullptr, *devices_cmd = nullptr,
           *export_cmd = nullptr;
  bool validate = false;
  bool strict_math = false;
  std::map<std::string, std::uint64_t> device_lacks;  // rayspace devices --device-lacks
#ifdef RAYSPACE_HAVE_VULKAN
  rayspace::app::DiffArgs diff;
  rayspace::app::ReplayArgs replay;
  rayspace::app::ExportArgs export_args;
  rayspace::app::MutateArgs mutate;
  rayspace::app::MutateMergeArgs mutate_merge;
  CLI::App* mutate_cmd = nullptr;
  CLI::App* mutate_merge_cmd = nullptr;
#endif
};

void AddAccuracy(CLI::App& app, Commands& cmds) {
  CLI::App* ac = cmds.accuracy_cmd = app.add_subcommand("accuracy", "Measure what accuracy costs: each precision mode of the cone-sphere and ray-triangle tests");
  ac->add_option("scene", cmds.accuracy.scene, "Scene JSON file")->required();
  ac->add_option("--data", cmds.accuracy.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  ac->add_option("--size", cmds.accuracy.size, "Image size WxH of the sampled frame (default 128x128)");
  ac->add_option("--samples", cmds.accuracy.samples, "Queries sampled per test (default 100000)");
  ac->add_option("--min-time", cmds.accuracy.min_time,
                 "Seconds each of a mode's three timed passes runs at the least; ns/test is their median (default 0.2)");
  ac->add_option("--out", cmds.accuracy.out, "Directory for <scene>-accuracy.md, .csv and .png (default .)");
  ac->add_flag("!--no-end-to-end", cmds.accuracy.end_to_end, "Skip the frames with each cone-sphere mode");
}

void AddBench(CLI::App& app, Commands& cmds) {
  CLI::App* bc = cmds.bench_cmd = app.add_subcommand(
      "bench", "Time every tracer on each scene and size in one run and print one table: median frame time, ratio to "
               "Embree, tests/s, peak memory and digest per configuration");
  rayspace::app::BenchArgs& b = cmds.bench;
  bc->add_option("scenes", b.scenes, "Scene JSON files")->required();
  bc->add_option("--data", b.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  bc->add_option("--sizes", b.sizes, "Image sizes WxH[,WxH...] (default 512x512); with several, how time grows with pixels");
  bc->add_option("--configs", b.configs,
                 "Configurations to run, comma-separated (default: all, in this order): " + rayspace::app::BenchConfigsHelp())
      ->check(CLI::Validator([](const std::string& v) { return v.empty() ? std::string("name one or more configurations") : std::string(); },
                             "", "NONEMPTY"));
  bc->add_option("--repetitions", b.repetitions, "Frames per configuration, scene and size, run in rounds of one frame per configuration; the table shows the median "
                 "(default 3)")->check(CLI::Range(1, 1000));
  bc->add_option("--threads", b.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  bc->add_option("--json", b.json, "Write every measurement as JSON to this file (-: to standard output, in place of "
                 "the tables)");
  rayspace::app::AddDeviceOption(*bc, b.device, b.device_lacks);
  rayspace::app::AddFaithfulOptions(*bc, b.faithful);
  bc->add_flag("--progress", b.progress, "Print each frame's time on stderr (default when stderr is a terminal)");
}

void AddShadowBench(CLI::App& app, Commands& cmds) {
  CLI::App* sc = cmds.shadow_bench_cmd = app.add_subcommand(
      "shadow-bench", "Time hard shadows through a point light's perspective grid (--algo grid) against Embree's occlusion "
                      "query on the same shadow rays, in one run: medians, rays/s and their ratio per scene");
  rayspace::app::ShadowBenchArgs& s = cmds.shadow_bench;
  sc->add_option("scenes", s.scenes, "Scene JSON files, each with a point light")->required();
  sc->add_option("--data", s.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  sc->add_option("--size", s.size, "Image size WxH whose first shadow rays are traced (default 512x512)");
  sc->add_option("--repetitions", s.repetitions, "Timings per scene; the table shows the median (default 5)")->check(CLI::Range(1, 1000));
  sc->add_option("--threads", s.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  sc->add_option("--grid-cells", s.grid_cells, "Cells per side of each face of the light's grid (default 200)")->check(CLI::Range(1u, 1024u));
  sc->add_flag("--closed-models", s.closed_models, "Front-face culling, as render --algo grid --closed-models");
  sc->add_option("--json", s.json, "Write the measurements as JSON to this file");
}

void AddData(CLI::App& app, Commands& cmds) {
  CLI::App* dc = app.add_subcommand("data", "The scene data: check the data root against the manifest of the files the "
                                            "bundled scenes need");
  dc->require_subcommand(1);
  CLI::App* cc = cmds.data_check_cmd = dc->add_subcommand(
      "check", "Check that every file the scenes need is under the data root with the manifest's size and SHA-256; "
               "one line per scene, exit 2 when a file is missing or differs");
  cc->add_option("scenes", cmds.data_check.scenes, "Scene JSON files or bundled scene names (default: every bundled scene)");
  cc->add_option("--data", cmds.data_check.data, "Data root (default: $RAYSPACE_DATA)");
}

// --sim-checks LIST: which of the simulated GPU's checkers run.
void AddSimChecksOption(CLI::App& cmd, std::string& checks) {
  cmd.add_option("--sim-checks", checks,
                 "The simulated GPU's checkers: all (default), none, or a comma-separated list of racecheck, initcheck, "
                 "synccheck, memcheck; one left out lets the kernel go on as a lenient device would")
      ->check([](const std::string& v) {
        std::string error;
        return rayspace::sim::ParseChecks(v, error) ? std::string() : error;
      });
}

// --device-model MODEL: the simulated GPU's float arithmetic.
void AddDeviceModelOption(CLI::App& cmd, std::string& model) {
  cmd.add_option("--device-model", model,
                 "The simulated GPU's float arithmetic: lavapipe (default: correctly rounded, the emulator's bits) or "
                 "worst[:SEED] (every operation Vulkan lets round loosely takes another permitted value: +, -, * and "
                 "conversions toward zero, / and inversesqrt off by 1-2 ULP, doubles at single precision, a*b+c fused "
                 "where not precise, min/max of a NaN the NaN, denormals flushed) or worst-nearest[:SEED] (the same with "
                 "+, -, * and conversions to nearest)")
      ->check([](const std::string& v) {
        std::string error;
        return rayspace::sim::ParseDeviceModel(v, error) ? std::string() : error;
      });
}

// --subgroup-layout LAYOUT: how the simulated GPU fills its subgroups.
void AddSubgroupLayoutOption(CLI::App& cmd, std::string& layout) {
  cmd.add_option("--subgroup-layout", layout,
                 "How the simulated GPU fills its subgroups: linear (default, lavapipe's: local index = subgroup x size + "
                 "lane), shuffled[:SEED] (invocations dealt to subgroups and lanes in a seeded order) or partial[:SEED] (each "
                 "subgroup launched with between half and all of its lanes, the rest inactive); Vulkan allows each without "
                 "full subgroups required")
      ->check([](const std::string& v) {
        std::string error;
        return rayspace::sim::ParseSubgroupLayout(v, error) ? std::string() : error;
      });
}

void AddSimulate(CLI::App& app, Commands& cmds) {
  rayspace::app::SimulateArgs& a = cmds.simulate;
  CLI::App* sc = cmds.simulate_cmd = app.add_subcommand(
      "simulate", "Run a reproducer written by `rayspace export` on the simulated GPU: the kernels' own SPIR-V executed on "
                  "the CPU, every read-back compared with the expected bytes; needs no Vulkan device");
  sc->add_option("dir", a.dir, "The reproducer's directory (export --out)")->required();
  sc->add_option("--subgroup-size", a.subgroup_size, "Invocations per subgroup (default 8, lavapipe's)")->check(CLI::Range(1, 128));
  AddSimChecksOption(*sc, a.sim_checks);
  AddDeviceModelOption(*sc, a.device_model);
  AddSubgroupLayoutOption(*sc, a.subgroup_layout);
}

// The simulated GPU's device options of a command that runs frames on it (`where`: how it is chosen).
void AddSimulatedDeviceOptions(CLI::App& cmd, const std::string& where, std::uint32_t& subgroup_size, std::string& checks,
                               std::string& model, std::string& layout, std::uint64_t& step_limit) {
  cmd.add_option("--subgroup-size", subgroup_size,
                 where + ": invocations per subgroup of the simulated GPU, and of the emulated kernels' mirrors (default 8, "
                 "lavapipe's)")
      ->check(CLI::Range(1, 128));
  AddSimChecksOption(cmd, checks);
  AddDeviceModelOption(cmd, model);
  AddSubgroupLayoutOption(cmd, layout);
  cmd.add_option("--step-limit", step_limit,
                 where + ": lane-instructions one workgroup of the simulated GPU may run before it counts as a hang (default "
                 "2^34; the kernel's fault is exit 7)")
      ->check(CLI::Range(std::uint64_t{1}, ~std::uint64_t{0}));
}

void AddRender(CLI::App& app, Commands& cmds) {
  CLI::App* rc = cmds.render_cmd = app.add_subcommand("render", "Render a scene through the emulated pipeline and check it with an oracle");
  rayspace::app::AddRenderOptions(*rc, cmds.render);
  AddSimulatedDeviceOptions(*rc, "--backend sim", cmds.render.subgroup_size, cmds.render.sim_checks, cmds.render.device_model,
                            cmds.render.subgroup_layout, cmds.render.step_limit);
}

#ifdef RAYSPACE_HAVE_VULKAN
void AddCompareOption(CLI::App& cmd, std::string& compare) {
  cmd.add_option("--compare", compare,
                 "bitwise: every word must equal the emulator's; relaxed: a differing word passes when a conformant "
                 "device may compute it (division, sqrt and denormals as Vulkan permits; raster differences on "
                 "triangle edges); auto: bitwise on lavapipe, relaxed elsewhere")
      ->check(CLI::IsMember({"auto", "bitwise", "relaxed"}));
}

void AddBackendsOption(CLI::App& cmd, std::string& backends, bool& given) {
  cmd.add_option_function<std::string>(
      "--backends",
      [&backends, &given](const std::string& v) {
        backends = v;
        given = true;
      },
      "The expected and the actual side: emu,vulkan (the kernels on a Vulkan device), emu,sim (the kernels' SPIR-V on "
      "the simulated GPU) or sim,vulkan (the same kernels on both: the simulated GPU expected); default emu,vulkan, or "
      "emu,sim where no Vulkan device is usable")
      ->check(CLI::IsMember({"emu,vulkan", "emu,sim", "sim,vulkan"}));
}

void AddDiffAndReplay(CLI::App& app, Commands& cmds) {
  CLI::App* dc = cmds.diff_cmd = app.add_subcommand("diff",
                                    "Run every pass of a frame on the emulator and the Vulkan kernels with the same "
                                    "inputs and compare bitwise (with --algo brute or embree the traces run on the "
                                    "host)");
  dc->add_option("scene", cmds.diff.scene, "Scene JSON file")->required();
  rayspace::app::AddFrameOptions(*dc, cmds.diff);
  dc->add_option("--report", cmds.diff.report, "Write the comparison as JSON to this file (-: to standard output, in "
                 "place of the summary)");
  dc->add_option("--junit", cmds.diff.junit, "Write the comparison as a JUnit XML report to this file: a test case per pass "
                 "call, failed with its first mismatch (docs/library.md)");
  dc->add_option("--inject", cmds.diff.inject, "Plant a fault in one kernel: PASS[:FAULT][@emu], FAULT a number or a "
                 "workgroup fault's name; @emu plants it in the emulated kernel (test use)");
  dc->add_option("--inject-each", cmds.diff.inject_each, "Plant each fault of a comma-separated list in turn, a frame "
                 "per fault on one device (only the faulted kernels' pipelines are made again); the report's \"faults\" "
                 "holds each frame's report; exit 6 when the workgroup checker stopped any frame, else 4 when any "
                 "diverged")
      ->delimiter(',');
  dc->add_flag("--no-impact", cmds.diff.no_impact, "After a divergence, do not measure what it does to the picture (two "
               "more frames, one on each backend alone, and the oracle's judgement of the changed rays)");
  rayspace::app::AddLocalSizeOption(*dc, cmds.diff.local_size);
  dc->add_option("--save-inputs", cmds.diff.save_inputs, "Write every pass call's inputs and options to DIR/NNNN-PASS/ "
                 "(for replay); DIR must be new or empty");
  AddCompareOption(*dc, cmds.diff.compare);
  AddBackendsOption(*dc, cmds.diff.backends, cmds.diff.backends_given);
  AddSimulatedDeviceOptions(*dc, "--backends emu,sim", cmds.diff.subgroup_size, cmds.diff.sim_checks, cmds.diff.device_model,
                            cmds.diff.subgroup_layout, cmds.diff.step_limit);
  dc->add_flag("--coverage-options", cmds.diff.coverage_options,
               "--backends emu,sim with --kernel: after the diff, probe the configurations that run every kernel's rarer "
               "paths (mutate's; 16x16 frames on the simulated GPU) and print which options reach the kernel's unreached "
               "lines (minutes)");
  dc->add_option("--path", cmds.diff.path,
                 "Hierarchy traversal: passes (traverse then reduce, default) or fused (traverse.compact, what render "
                 "runs by default; the emulator runs its workgroup mirror unless --no-check-workgroups with the forward "
                 "schedule asks for its SIMD lanes)")
      ->check(CLI::IsMember({"fused", "passes"}));
  dc->add_flag("--progress", cmds.diff.progress, "Print each pass as k of n with its time and an ETA on stderr (default "
               "when stderr is a terminal)");
  CLI::App* pc = cmds.replay_cmd = app.add_subcommand("replay", "Run one pass call saved by diff --save-inputs on both backends and compare");
  pc->add_option("dir", cmds.replay.dir, "Directory of the saved call (DIR/NNNN-PASS); the options the diff ran it "
                 "with (--split-bytes, --max-groups, --local-size, --inject, --compare, --schedule, --check-workgroups, "
                 "--kernel, --strict-math) apply unless given here")->required();
  pc->add_option("--report", cmds.replay.report, "Write the comparison as JSON to this file (-: to standard output, in "
                 "place of the summary)");
  pc->add_option("--inject", cmds.replay.inject, "Plant a fault in one kernel: PASS[:FAULT][@emu], or none (default: the "
                 "fault the diff planted when it saved the call; test use)");
  rayspace::app::AddKernelModelOptions(*pc, cmds.replay.model);
  rayspace::app::AddLocalSizeOption(*pc, cmds.replay.local_size);
  AddCompareOption(*pc, cmds.replay.compare);
  AddBackendsOption(*pc, cmds.replay.backends, cmds.replay.backends_given);
  rayspace::app::AddKernelOption(*pc, cmds.replay.kernels);
  rayspace::app::AddDeviceOption(*pc, cmds.replay.device, cmds.replay.device_lacks);
  rayspace::app::AddLimitOptions(*pc, cmds.replay.split_bytes, cmds.replay.max_groups);
}

void AddExport(CLI::App& app, Commands& cmds) {
  rayspace::app::ExportArgs& e = cmds.export_args;
  CLI::App* ec = cmds.export_cmd = app.add_subcommand(
      "export", "Write a call saved by diff --save-inputs as a reproducer for a Vulkan driver developer: SPIR-V, input "
                "and expected buffers, the dispatch sequence, and a C program that needs only the Vulkan loader");
  ec->add_option("dir", e.dir, "Directory of the saved call (DIR/NNNN-PASS)")->required();
  ec->add_option("--out", e.out, "Directory to write the reproducer into (new or empty)")->required();
  ec->add_option_function<std::string>(
      "--inject",
      [&e](const std::string& v) {
        e.inject = v;
        e.inject_given = true;
      },
      "The planted fault to set in the exported kernel: PASS[:FAULT] (default: the one the saved call records)");
  ec->add_option_function<std::vector<std::string>>(
      "--kernel",
      [&e](const std::vector<std::string>& v) {
        e.kernels = v;
        e.kernels_given = true;
      },
      "Export your kernel for a pass in place of the built-in one: PASS=FILE (.comp or .spv, repeatable; default: the "
      "kernels the saved call records)");
  rayspace::app::AddDeviceOption(*ec, e.device, e.device_lacks);
  ec->add_option("--local-size", e.local_size, "Workgroup size of the kernels (default: as recorded, else 64)")
      ->check(CLI::Range(1, 1024));
  rayspace::app::AddLimitOptions(*ec, e.split_bytes, e.max_groups);
}
#endif

#ifdef RAYSPACE_HAVE_VULKAN
void AddMutate(CLI::App& app, Commands& cmds) {
  CLI::App* mc = cmds.mutate_cmd = app.add_subcommand(
      "mutate", "Mutants of every GLSL kernel (comparisons, operators, constants, barriers, bindings, components, loop "
                "bounds), each run through the pass-by-pass diff on a small frame, and spirv-opt variants that must diff "
                "equal (docs/verification.md)");
  rayspace::app::MutateArgs& m = cmds.mutate;
  mc->add_option("scene", m.scene, "Scene JSON file (default scenes/cornell-mirrors.json)");
  mc->add_option("--pass", m.passes, "Only these passes' kernels (repeatable; default every kernel the scene runs, and their include files)");
  mc->add_option("--config", m.configs, "Only these diff configurations (repeatable; default all: docs/verification.md lists them)");
  mc->add_option("--limit", m.limit, "Mutants to run, taken in turn from each file's seeded shuffle, the files in a seeded order; 0: every one (default 30)")
      ->check(CLI::Range(0, 1000000));
  mc->add_option("--seed", m.seed, "Seed of the choice: a number, a word, or 'commit' (this binary's commit) (default 1)");
  mc->add_option("--report", m.report, "Write every mutant, verdict and variant as JSON to this file");
  mc->add_option("--shard", m.shard, "Run only the mutants and variants I, I+N, ... (0 <= I < N) of the choice; combine the "
                 "shards' reports with `mutate merge` into the bytes one run writes (default 0/1)");
  CLI::App* merge = cmds.mutate_merge_cmd = mc->add_subcommand("merge", "Merge the --report files of `mutate --shard` runs, every "
                                                                         "shard of one run once, into one run's report");
  merge->add_option("out", cmds.mutate_merge.out, "The merged report (JSON)")->required();
  merge->add_option("shards", cmds.mutate_merge.shards, "The shards' reports")->required();
  merge->add_option("--junit", cmds.mutate_merge.junit, "Also write the merged run as a JUnit XML report to this file");
  mc->add_option("--junit", m.junit, "Write the mutants and variants as a JUnit XML report to this file: a test case per mutant, "
                 "failed when it survives unexplained (docs/library.md)");
  mc->add_option("--data", m.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  mc->add_option("--size", m.size, "Frame size WxH of each diff (default 32x32)");
  mc->add_option("--variants", m.variants, "spirv-opt variants to run (kernel x recipe, seeded): a count or 'all' (default 2)");
  mc->add_option("--timeout", m.timeout, "Seconds per diff before a mutant counts as hung (default 60)")->check(CLI::Range(1, 3600));
  mc->add_option("--jobs", m.jobs, "Diffs run at once (default 1)")->check(CLI::Range(1, 64));
  mc->add_option("--survivors", m.survivors, "JSON of explained survivors ({\"mutants\": {ID: {\"class\", \"why\", \"source\"}}}; an entry applies only while its mutant's line reads as its source); default the "
                                             "source tree's docs/mutation-survivors.json, 'none' for no classifications");
  mc->add_option("--only", m.only, "Only mutants whose id (file:line:column:operator:replacement) matches this regular expression");
  mc->add_option("--work", m.work, "Keep each mutant's files, diff log and report in this directory (default: a temporary one, removed)");
  CLI::Option* list = mc->add_flag("--list", m.list, "Print the chosen mutants and exit");
  CLI::Option* cases = mc->add_flag("--cases-only", m.cases_only,
                                    "Replay every kernel case (docs/verification.md) with the built-in kernels and exit: 0 when each "
                                    "is equal, 4 when one is not, 6 for a checker's finding on the simulator (a mutant run replays only the cases of the "
                                    "passes its mutants change)");
  cases->excludes(list);
  // What chooses mutants or renders frames does nothing here: refused, not ignored.
  for (const char* unused : {"scene", "--pass", "--config", "--limit", "--seed", "--shard", "--junit", "--variants", "--jobs",
                             "--survivors", "--only", "--size", "--data"})
    cases->excludes(mc->get_option(unused));
  mc->add_option("--backends", m.backends,
                 "Where each mutant's diffs run: emu,vulkan (default), emu,sim (the kernels' SPIR-V on the simulated GPU, its "
                 "checkers on) or emu,vulkan,sim (both: each side's score, and the mutants whose verdicts differ, in one report)")
      ->check(CLI::IsMember({"emu,vulkan", "emu,sim", "emu,vulkan,sim"}));
}

// The replay options the command line gives; the rest come from the saved call's recording.
void NoteGivenReplayOptions(Commands& cmds) {
  if (!cmds.replay_cmd->parsed()) return;
  for (const CLI::Option* o : cmds.replay_cmd->get_options())
    if (o->count() > 0) cmds.replay.given.insert(o->get_name());
  if (cmds.strict_math) cmds.replay.given.insert("--strict-math");
}
#endif

// Flags the chosen mode does not use: a warning each, before the run.
// The settings the parsed command runs with, made once: RS_CHECK failures end the run with an error,
// the workgroup checker is off unless the command asks for it (--check-workgroups, an @emu fault),
// and --validate, --strict-math and --device-lacks as given. The timed frames (render, bench) leave
// new buffers as the pool hands them out; diff and replay poison them.
rayspace::Settings CommandSettings(const Commands& cmds) {
  rayspace::Settings s;
  s.check = false;
  s.check_failures_throw = true;
  s.validation = cmds.validate ? rayspace::Validation::kGpuAssisted : rayspace::Validation::kFromEnvironment;
  s.strict_math = cmds.strict_math;
  s.poison_new_buffers = !(cmds.render_cmd->parsed() || cmds.bench_cmd->parsed());
  for (const auto* lacks : {&cmds.device_lacks, &cmds.render.device_lacks, &cmds.bench.device_lacks
#ifdef RAYSPACE_HAVE_VULKAN
                            , &cmds.diff.device_lacks, &cmds.replay.device_lacks, &cmds.export_args.device_lacks
#endif
       })
    s.device_lacks.insert(lacks->begin(), lacks->end());
  return s;
}

void WarnIgnoredOptions(const Commands& cmds) {
  if (cmds.render_cmd->parsed())
    rayspace::app::WarnIgnored("render", rayspace::app::IgnoredRenderOptions(*cmds.render_cmd, cmds.render));
  if (cmds.bench_cmd->parsed())
    rayspace::app::WarnIgnored("bench", rayspace::app::IgnoredBenchOptions(*cmds.bench_cmd, cmds.bench));
#ifdef RAYSPACE_HAVE_VULKAN
  if (cmds.diff_cmd->parsed())
    rayspace::app::WarnIgnored("diff", rayspace::app::IgnoredFrameOptions(*cmds.diff_cmd, cmds.diff, cmds.diff.path == "fused"));
#endif
}

rayspace::ExitCode Run(const Commands& cmds) {
  using rayspace::ExitCode;
  if (cmds.render_cmd->parsed()) {
    rayspace::app::ValidateFrameArgs(cmds.render);
    return rayspace::app::RunRender(cmds.render);
  }
  if (cmds.accuracy_cmd->parsed()) return rayspace::app::RunAccuracy(cmds.accuracy);
  if (cmds.bench_cmd->parsed()) return rayspace::app::RunBench(cmds.bench);
  if (cmds.shadow_bench_cmd->parsed()) return rayspace::app::RunShadowBench(cmds.shadow_bench);
  if (cmds.reproduce_cmds.second->parsed()) return rayspace::reproduce::RunMerge(cmds.reproduce);
  if (cmds.reproduce_cmds.first->parsed()) return rayspace::reproduce::RunReproduce(cmds.reproduce, rayspace::reproduce::RenderConfig);
  if (cmds.data_check_cmd->parsed()) return rayspace::app::RunDataCheck(cmds.data_check);
  if (cmds.simulate_cmd->parsed()) return rayspace::app::RunSimulate(cmds.simulate);
#ifdef RAYSPACE_HAVE_VULKAN
  if (cmds.diff_cmd->parsed()) {
    rayspace::app::ValidateFrameArgs(cmds.diff);
    return rayspace::app::RunDiff(cmds.diff);
  }
  if (cmds.replay_cmd->parsed()) return rayspace::app::RunReplay(cmds.replay);
  if (cmds.devices_cmd->parsed()) return rayspace::app::RunDevices();
  if (cmds.export_cmd->parsed()) return rayspace::app::RunExport(cmds.export_args);
  if (cmds.mutate_merge_cmd->parsed()) return rayspace::app::RunMutateMerge(cmds.mutate_merge);
  if (cmds.mutate_cmd->parsed()) return rayspace::app::RunMutate(cmds.mutate);
#endif
  return ExitCode::kOk;
}

// render --backend sim or vulkan: a simulated checker's finding (6), or a device that could not finish
// a call (7: a failed Vulkan call, the step limit); a kernel's output breaking its contract stays a
// failure (1).
rayspace::ExitCode BackendFailureExit(const rayspace::emu::BackendError& e) {
  using rayspace::ExitCode;
  if (!e.checker().empty() || e.device_fault()) {
    std::fprintf(stderr, "rayspace: %s: %s\n", e.checker().empty() ? "backend failed" : e.checker().c_str(), e.what());
    return e.checker().empty() ? ExitCode::kBackendFault : ExitCode::kWorkgroupFault;
  }
  std::fprintf(stderr, "rayspace: failure: %s\n", e.what());
  return ExitCode::kInternal;
}

}  // namespace

// An empty value is never what a user means by a path, a size or a name: `--out ""` would fall
// back to the default as if the option were absent. Every option and argument that takes a value
// refuses an empty one, except --inject, where "" means no fault (replay: without the recorded one),
// and --data, where "" means no data root given (as with RAYSPACE_DATA unset).
void RefuseEmptyValues(CLI::App& app) {
  const CLI::Validator non_empty([](const std::string& v) { return v.empty() ? std::string("an empty value") : std::string(); },
                                 "", "NONEMPTY");
  for (CLI::Option* o : app.get_options())
    if (o->get_items_expected_min() > 0 && o->get_name() != "--inject" && o->get_name() != "--data") o->check(non_empty);
  for (CLI::App* sub : app.get_subcommands({})) RefuseEmptyValues(*sub);
}

int main(int argc, char** argv) {
  using rayspace::ExitCode;
  CLI::App app{"rayspace: emulator and verification suite for GPU secondary-ray tracing with ray-space hierarchies"};
  app.require_subcommand(1);
  app.fallthrough();  // --validate may follow the command's own options
  app.footer(rayspace::ExitCodeHelp());  // before the subcommands, which inherit it
  app.set_version_flag("--version", [] { return rayspace::app::VersionText(); }, "Print the version, commit, backends and libraries");
  Commands cmds;
  app.add_flag("--strict-math", cmds.strict_math,
               "Vulkan: the kernels divide and take square roots correctly rounded in integer arithmetic, so they "
               "give the emulator's bits on any conformant device (Vulkan lets a device round / and sqrt loosely)");
  app.add_flag("--validate", cmds.validate,
               "Vulkan: run with the Khronos validation layer, synchronization validation and GPU-assisted validation "
               "(descriptor accesses checked against their bounds); any message fails the Vulkan call after which it was "
               "reported (RAYSPACE_VALIDATE=gpu does the same, RAYSPACE_VALIDATE=1 without GPU-assisted validation)");
  AddRender(app, cmds);
  AddAccuracy(app, cmds);
  AddBench(app, cmds);
  AddShadowBench(app, cmds);
  cmds.reproduce_cmds = rayspace::reproduce::AddReproduceCommand(app, cmds.reproduce);
  AddData(app, cmds);
  AddSimulate(app, cmds);
#ifdef RAYSPACE_HAVE_VULKAN
  AddDiffAndReplay(app, cmds);
  AddExport(app, cmds);
  AddMutate(app, cmds);
  cmds.devices_cmd = app.add_subcommand("devices", "List the Vulkan devices, each requirement of rayspace met or not, the "
                                                   "device used without --device and how diff compares on it");
  rayspace::app::AddDeviceLacksOption(*cmds.devices_cmd, cmds.device_lacks);
#endif
  RefuseEmptyValues(app);
  rayspace::app::SetArguments(argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    std::fputs(e.what(), stdout);
    return 0;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "rayspace: error: %s\n", e.what());
    return ToInt(ExitCode::kBadInput);
  }
#ifdef RAYSPACE_HAVE_VULKAN
  NoteGivenReplayOptions(cmds);
#endif
  const rayspace::ScopedSettings settings(CommandSettings(cmds));
  WarnIgnoredOptions(cmds);
  ExitCode code = ExitCode::kOk;
  try {
    code = Run(cmds);
  } catch (const rayspace::InputError& e) {
    std::fprintf(stderr, "rayspace: error: %s\n", e.what());
    return ToInt(ExitCode::kBadInput);
  } catch (const rayspace::CheckFailure& e) {
    std::fprintf(stderr, "rayspace: internal check failed: %s\n", e.what());
    return ToInt(ExitCode::kInternal);
  } catch (const rayspace::emu::DeviceOutputError& e) {
    // A backend's kernel returned an index or count out of range: the device or the kernel is wrong,
    // not the input, and the frame stopped before anything read with it.
    std::fprintf(stderr, "rayspace: device output error: %s\n", e.what());
    return ToInt(ExitCode::kInternal);
  } catch (const rayspace::wg::CheckError& e) {
    std::fprintf(stderr, "rayspace: workgroup checker: %s\n", e.what());
    return ToInt(ExitCode::kWorkgroupFault);
  } catch (const rayspace::emu::BackendError& e) {
    return rayspace::ToInt(BackendFailureExit(e));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rayspace: failure: %s\n", e.what());
    return ToInt(ExitCode::kInternal);
  }
#ifdef RAYSPACE_HAVE_VULKAN
  if (rayspace::vk::ValidationFailedAtExit() && code == ExitCode::kOk) return ToInt(ExitCode::kInternal);
#endif
  return ToInt(code);
}
