#include "frame_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/scene.h"

#ifdef RAYSPACE_HAVE_VULKAN
#include "rayspace/gpu/requirements.h"
#endif

namespace rayspace::app {

namespace {

std::string PresetHelp() {
  std::string help = "Work as a paper did: thesis (the CRSH thesis: the readings its published numbers support, "
                     "docs/reproduce.md) or roger (Roger et al. 2007); none keeps rayspace's own choices. A preset sets "
                     "switches the command line does not give:";
  for (const char* name : {"thesis", "roger"}) {
    help += fmt::format(" {} =", name);
    for (const std::string& w : FaithfulPreset(name)) help += " " + w;
    help += ";";
  }
  help.pop_back();
  return help;
}

// Applies the preset's switches that `command` has and the command line did not give, through the
// options themselves, so each value passes the same checks as when typed.
void ResolvePreset(CLI::App& command, const std::string& preset) {
  const std::vector<std::string> words = FaithfulPreset(preset);
  for (std::size_t i = 0; i < words.size(); ++i) {
    const bool has_value = i + 1 < words.size() && words[i + 1].rfind("--", 0) != 0;
    CLI::Option* opt = command.get_option_no_throw(words[i]);
    const std::string value = has_value ? words[i + 1] : "true";
    if (has_value) ++i;
    if (opt == nullptr || opt->count() > 0) continue;
    opt->add_result(value);
    opt->run_callback();
  }
}

}  // namespace

void AddFaithfulOptions(CLI::App& command, FaithfulArgs& args) {
  command.add_option("--faithful", args.preset, PresetHelp())
      ->check(CLI::IsMember({"none", "thesis", "roger"}))
      ->capture_default_str();
  command.parse_complete_callback([&command, &args] { ResolvePreset(command, args.preset); });
  command
      .add_option("--hash-order", args.hash_order,
                  "Direction part of the CRSH hash keys: interleaved (polar and azimuth bits alternate) or polar-first "
                  "(all polar bits above the azimuth's, as the thesis prints it)")
      ->check(CLI::IsMember({"interleaved", "polar-first"}))
      ->capture_default_str();
  command
      .add_option("--hash-bits", args.hash_bits,
                  fmt::format("Shadow hash keys: cells bits per angle, polar and azimuth (1 to {}: the light index takes "
                              "{} of the key's {} bits)",
                              MaxHashBits(), emu::HashConfig{}.light_bits, layout::kHashKeyBits))
      ->check(CLI::Range(1, MaxHashBits()))
      ->capture_default_str();
  command
      .add_option("--shadow-rule", args.shadow_rule,
                  "Shadow rays: all (one per covered pixel and light) or lit (only where the light is in front of "
                  "the surface, n.l > 0, as the thesis counts them); the image is the same")
      ->check(CLI::IsMember({"all", "lit"}))
      ->capture_default_str();
  command
      .add_option("--shadow-bounces", args.shadow_bounces,
                  "Shadow rays after every bounce (all) or from the primary hits only (first, the thesis's one shadow "
                  "batch; later bounces then shade with every light unoccluded)")
      ->check(CLI::IsMember({"all", "first"}))
      ->capture_default_str();
  command.add_flag("--one-object", args.one_object,
                   "Merge all of the scene's objects into one (one bounding sphere), as the thesis's Sponza; same hits");
  command
      .add_option("--cone-test", args.cone_test,
                  "The traversal's cone-sphere test: conservative (never loses a hit), printed (the thesis's eq. 3.16 "
                  "as printed, no margins; it can lose hits, which the oracle counts) or printed-signed (the same without "
                  "the absolute value of the distance along the axis: one cone, not two apex to apex); the printed ones "
                  "trace --objects flat")
      ->check(CLI::IsMember({"conservative", "printed", "printed-signed"}))
      ->capture_default_str();
  command
      .add_option("--leaf-test", args.leaf_test,
                  "Rays of a surviving leaf node against its triangle: node (each ray's ray-triangle test) or ray-sphere "
                  "(each ray first against the triangle's bounding sphere, as Roger et al.; counted as leaf sphere "
                  "tests); same hits")
      ->check(CLI::IsMember({"node", "ray-sphere"}))
      ->capture_default_str();
  command
      .add_option("--child-merge", args.child_merge,
                  "How a parent node unites its children: sequential (one after another, as the thesis folds them) "
                  "or pairwise (a balanced binary tree: smaller spheres); same hits")
      ->check(CLI::IsMember({"sequential", "pairwise"}))
      ->capture_default_str();
}

FaithfulArgs FaithfulFromWords(const std::vector<std::string>& words) {
  FaithfulArgs args;
  CLI::App app;
  AddFaithfulOptions(app, args);
  std::string text;
  for (const std::string& w : words) text += (text.empty() ? "" : " ") + w;
  try {
    app.parse(std::vector<std::string>(words.rbegin(), words.rend()));  // CLI11 reads the vector from its back
  } catch (const CLI::ParseError& e) {
    ThrowInput("{}: {}", text, e.what());
  }
  return args;
}

FaithfulArgs FaithfulFromPreset(const std::string& name) { return FaithfulFromWords({"--faithful", name}); }

void AddKernelModelOptions(CLI::App& command, KernelModelArgs& args) {
  command.add_option("--schedule", args.schedule,
                     "The order the invocations of each emulated workgroup phase run in, and on the simulated GPU the "
                     "order of its workgroups and subgroups: forward, reverse or random[:SEED] (results must not change)")
      ->check([](const std::string& spec) {
        try {
          ParseSchedule(spec);
          return std::string();
        } catch (const InputError& e) {
          const std::string m = e.what();  // CLI11 names the option itself
          return m.substr(m.find('\''));
        }
      });
  command.add_flag("--check-workgroups,!--no-check-workgroups", args.check,
                   fmt::format("Emulator: check every shared-memory access of the workgroup kernels for races, reads "
                               "of unwritten words and divergent barriers (always on when a fault is planted with @emu; "
                               "default {})", args.check ? "on" : "off"));
}

namespace {

// --algo tl's own switches.
void AddTlOptions(CLI::App& command, FrameArgs& args) {
  command.add_option("--lists", args.lists, "--algo tl: traversal lists, 1 (+x), 2 (+-x), 6 (+-x, +-y, +-z) or 8 (the diagonals)")
      ->check(CLI::IsMember({1u, 2u, 6u, 8u}))
      ->capture_default_str();
  command
      .add_option("--node-order", args.node_order,
                  "--algo tl: a node's children along each list by the low end of their projection (earliest-first) "
                  "or its high end (latest-last)")
      ->check(CLI::IsMember({"earliest-first", "latest-last"}))
      ->capture_default_str();
  command
      .add_option("--backface-cull", args.backface_cull,
                  "--algo tl: one-sided triangles (a ray meets a triangle only from the side (v1 - v0) x (v2 - v0) points "
                  "to; the oracle applies the same rule) and each list drops the triangles its rays can only meet from "
                  "behind (Toczek et al.'s back-face culling)")
      ->check(CLI::IsMember({"off", "on"}))
      ->capture_default_str();
  command
      .add_option("--polygon-heads", args.polygon_heads,
                  "--algo tl: per-polygon list heads for secondary rays (Toczek et al. section 3.1): a ray leaving or "
                  "reaching a triangle walks only the part of its list not wholly behind the triangle's plane (simple), "
                  "nor behind the list's facet planes through the triangle (regular)")
      ->check(CLI::IsMember({"off", "simple", "regular"}))
      ->capture_default_str();
  command
      .add_option("--primary", args.primary,
                  "primary visibility: the raster's G-buffer (raster), or also an eye ray per pixel traced beside it "
                  "through the traversal lists (tl, --algo tl), the eye's perspective grid (grid, --algo grid: one "
                  "cell of about 100x100 pixels per ray, Hunt and Mark's eye rays) or Embree's BVH (embree, --algo "
                  "embree: the reference's eye rays); checked by the oracle and counted, the G-buffer still shades")
      ->check(CLI::IsMember({"raster", "tl", "grid", "embree"}))
      ->capture_default_str();
  command
      .add_option("--frustum-cull", args.frustum_cull,
                  "--primary tl: per screen cell of 16x16 pixels, the part of each list its eye rays can reach (Toczek et "
                  "al.'s frustum culling, the pass tl.cells)")
      ->check(CLI::IsMember({"off", "on"}))
      ->capture_default_str();
}

// --algo grid's own switches.
void AddGridOptions(CLI::App& command, FrameArgs& args) {
  command
      .add_option("--grid-cells", args.grid_cells,
                  "--algo grid: cells per side of each face of a point light's perspective grid (Hunt and Mark's 200; six "
                  "faces about the light)")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  command
      .add_option("--grid-regular", args.grid_regular,
                  "--algo grid: cells of the regular grid along the scene box's longest side (the others in proportion), "
                  "for every ray that is not a point light's shadow ray")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  command
      .add_option("--grid-regular-cells", args.grid_regular_cells,
                  "--algo grid: size the regular grid by its cells instead: the count along the longest side (1 to 1024) "
                  "whose grid holds the number closest to this (Hunt and Mark compare grids of about equal cells)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 30))
      ->excludes("--grid-regular");
  command
      .add_option("--grid-area", args.grid_area,
                  "--algo grid: each area light's 3D perspective grid about its centre, NxNxD (cells per face side, "
                  "twice, then depth slices; Hunt and Mark's 200x200x4), or 'regular': its shadow rays step through the "
                  "regular grid instead (their Table 5 compares the two)")
      ->check(CLI::Validator(
          [](std::string& text) {
            emu::grid::Options o;
            return ParseGridArea(text, o);
          },
          "NxNxD|regular"))
      ->capture_default_str();
  command
      .add_option("--grid-area-near", args.grid_area_near,
                  "--algo grid: an area light's 3D grid begins this many times the light's reach from its centre; "
                  "closer in, its rays walk the regular grid")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  command
      .add_option("--grid-secondary", args.grid_secondary,
                  "--algo grid: what reflection and refraction rays walk: the regular grid, or a 3D perspective grid about "
                  "the eye (--grid-area's cells; docs/grids.md measures both)")
      ->check(CLI::IsMember({"regular", "perspective"}))
      ->capture_default_str();
  command.add_flag("--closed-models", args.closed_models,
                   "--algo grid: Hunt and Mark's front-face culling: a light's grid holds only the triangles facing away "
                   "from it and a surface facing away is in shadow untraced; right for closed meshes only (an open one "
                   "is warned of, and the shadow results it changes are counted against the oracle)");
}

// --levels (alias --depth): a number of levels, or auto (emu::AutoLevels from the image's pixels).
void AddLevelsOption(CLI::App& command, FrameArgs& args) {
  command
      .add_option_function<std::string>(
          "--levels,--depth",
          [&args](const std::string& v) {
            args.depth_given = true;
            args.depth_auto = v == "auto";
            if (!args.depth_auto) args.depth = std::stoi(v);
          },
          fmt::format("Hierarchy levels, or auto: the fewest (at least 2) that leave at most {} top nodes for the "
                      "image's pixels (rah-quadtree: log2 of the image size unless given); --depth is the same "
                      "option. Not the bounces: see --bounces",
                      emu::kAutoTopNodes))
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            if (v == "auto") return {};
            int n = 0;
            std::size_t used = 0;
            try {
              n = std::stoi(v, &used);
            } catch (const std::exception&) {
              used = 0;
            }
            return used == v.size() && n >= 1 && n <= 12 ? "" : "'" + v + "' is not auto or an integer in [1 - 12]";
          },
          "INT in [1 - 12] or auto"))
      ->default_str(std::to_string(args.depth));
}

}  // namespace

void AddFrameOptions(CLI::App& command, FrameArgs& args) {
  command
      .add_option("--algo", args.algo,
                  "Tracer for secondary rays: crsh (ray hashing + sorting, object spheres), rah (same hierarchy "
                  "over unsorted rays), rah-quadtree (Roger et al.'s screen quadtree), tl (Toczek et al.'s "
                  "traversal lists), grid (Hunt and Mark's perspective grids), brute (emulated direct tracer), embree")
      ->check(CLI::IsMember(AlgorithmNames()))
      ->capture_default_str();
  command.add_option("--subdivision", args.subdivision, "Children per hierarchy node (rah-quadtree: always 4)")
      ->check(CLI::IsMember({4, 8, 16}))
      ->capture_default_str();
  // Levels of the ray hierarchy, not bounces (--bounces): --depth is its older name, kept working.
  AddLevelsOption(command, args);
  command
      .add_option("--bounces", args.bounces,
                  fmt::format("Reflection and refraction bounces, in place of the scene's max_depth (0 to {})", kMaxDepth))
      ->check(CLI::Range(0, kMaxDepth));
  command
      .add_option("--objects", args.objects,
                  "Hierarchy tracers against the objects: flat (every triangle of every object whose sphere a top "
                  "node may meet, the thesis's), tree (the cone hierarchy and each object's bounding-sphere tree "
                  "descended together; emulator only) or auto (per ray batch: tree when the batch's leaf cones spread "
                  "by at least 0.1, see `leaf_spread` in --stats, or an object has 16,384 triangles or more, else "
                  "flat; flat on Vulkan)")
      ->check(CLI::IsMember({"flat", "tree", "auto"}))
      ->capture_default_str();
  AddTlOptions(command, args);
  AddGridOptions(command, args);
  command.add_option("--tree-leaf", args.tree_leaf, "--objects tree, --algo tl: an object-tree node of at most this many triangles is a leaf")
      ->check(CLI::Range(1u, 1024u))
      ->capture_default_str();
  command
      .add_option("--tree-big", args.tree_big,
                  "--objects tree, --algo tl: a triangle whose radius is at least this fraction of its node's stays the node's own "
                  "(--algo tl: 0.7 unless given)")
      ->check(CLI::Validator(
          [](std::string& v) {  // Range lets NaN through: every comparison with it is false
            const float f = std::strtof(v.c_str(), nullptr);
            return std::isfinite(f) ? std::string() : "Value " + v + " is not a finite number";
          },
          "FINITE"))
      ->check(CLI::Range(0.001f, 1000.0f))
      ->capture_default_str()
      ->each([&args](const std::string&) { args.tree_big_given = true; });
  command.add_option("--reduction", args.reduction, "Stream reduction: hierarchical (Roger et al.) or scan")
      ->check(CLI::IsMember({"hierarchical", "scan"}))
      ->capture_default_str();
  command.add_option("--component-size", args.component_size, "Component size s of the hierarchical reduction")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  command
      .add_option("--pair-capacity", args.pair_capacity,
                  "Pairs one traversal level may hold; more splits the triangle batch. At least "
                  "subdivision^(levels-1), the pairs one top node and one triangle can reach (8 with the defaults, "
                  "4^(levels-1) with rah-quadtree); --objects tree may need more, and says so")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 30).description("UINT in [subdivision^(levels-1) - 2^30]"))
      ->capture_default_str();
  command.add_option("--size", args.size, "Image size WxH (overrides the scene)");
  command.add_option("--data", args.data, "Data root for mesh paths (default: $RAYSPACE_DATA)");
  AddDeviceOption(command, args.device, args.device_lacks);
  AddLimitOptions(command, args.split_bytes, args.max_groups);
  AddKernelOption(command, args.kernels);
  AddKernelModelOptions(command, args.model);
  AddFaithfulOptions(command, args.faithful);
}

void AddLimitOptions(CLI::App& command, std::size_t& split_bytes, std::uint32_t& max_groups) {
  command
      .add_option("--split-bytes", split_bytes,
                  "Vulkan: bind at most this many bytes per storage buffer when below the device's "
                  "maxStorageBufferRange, so that passes split and page their buffers on small frames (test use)")
      ->check(CLI::Range(std::size_t{4096}, std::size_t{1} << 40));
  command
      .add_option("--max-groups", max_groups,
                  "Vulkan: launch at most this many workgroups per row when below the device's "
                  "maxComputeWorkGroupCount, so that large launches fold into rows (test use)")
      ->check(CLI::Range(1u, 65535u));
}

void AddDeviceOption(CLI::App& command, int& device, std::map<std::string, std::uint64_t>& lacks) {
  command
      .add_option("--device", device,
                  "Vulkan device index (default: a discrete GPU, else an integrated one, ..., else lavapipe: "
                  "`rayspace devices` shows the choice); render uses it with --backend vulkan")
      ->check(CLI::Range(0, 64));
  AddDeviceLacksOption(command, lacks);
}

void AddDeviceLacksOption(CLI::App& command, std::map<std::string, std::uint64_t>& out) {
#ifdef RAYSPACE_HAVE_VULKAN
  command.add_option_function<std::vector<std::string>>(
      "--device-lacks",
      [&out](const std::vector<std::string>& specs) {
        vk::Lacks lacks;
        for (const std::string& s : specs) {
          const auto eq = s.find('=');
          std::uint64_t value = 0;
          if (eq != std::string::npos) {
            const std::string v = s.substr(eq + 1);
            if (v.empty() || v.size() > 19 || v.find_first_not_of("0123456789") != std::string::npos)
              throw CLI::ValidationError("--device-lacks", "'" + s + "': the value after '=' must be a number");
            value = std::stoull(v);
          }
          lacks[s.substr(0, eq)] = value;
        }
        out = std::move(lacks);
      },
      "Vulkan: make the device look as if it lacked a requirement: NAME (a feature, or a limit as 0) or NAME=VALUE "
      "(a limit); names as `rayspace devices` prints them (test use)");
#else
  (void)command;
  (void)out;
#endif
}

void AddKernelOption(CLI::App& command, KernelFiles& kernels) {
  command.add_option("--kernel", static_cast<std::vector<std::string>&>(kernels),
                     "Vulkan: run a user's kernel for one pass in place of the built-in one: PASS=FILE (.comp or .spv), "
                     "checked against the pass's contract (docs/kernels.md); repeatable");
}

void AddLocalSizeOption(CLI::App& command, int& local_size) {
  command.add_option("--local-size", local_size, "Workgroup size of every compute kernel (results must not change)")
      ->check(CLI::Range(1, 1024));
}

}  // namespace rayspace::app
