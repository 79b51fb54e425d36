#include "rayspace/reproduce/configs.h"

#include <fmt/format.h>

#include "rayspace/reproduce/faithful_presets.h"
#include "rayspace/reproduce/fit_thesis.h"

namespace rayspace::reproduce {

const std::vector<SceneChoice>& ThesisScenes() {
  static const std::vector<SceneChoice> scenes = {
      {"OFFICE", {{"office.json", "stand-in office model, 2 lights"}}, 1},
      {"CORNELL", {{"cornell-mirrors.json", "stand-in: cornell-mirrors, shadow rays after each of 2 bounces"}}, 2},
      {"SPONZA",
       {{"sponza-thesis-fit-2.json",
         "34 objects, not one mesh; camera and light fitted on RAH s8 d2's rays and level hits among plausible poses (docs/reproduce.md, \"Fits\", "
         "protocol 2)"},
        {"sponza-thesis-fit.json",
         "34 objects, not one mesh; camera and light fitted on RAH s8 d2's rays and level hits (docs/reproduce.md, \"Fits\", protocol 1)"},
        {"sponza-thesis.json", "34 objects, not one mesh; our viewpoint, chosen for the thesis's shadow-ray count (its camera is not published)"}},
       1,
       true},
  };
  return scenes;
}

int FitProtocolOfScene(const std::string& scene_file) {
  for (int protocol = 1; protocol <= kFitProtocolLatest; ++protocol)
    if (scene_file == FittedSceneStem(protocol) + ".json") return protocol;
  return 0;
}

const std::vector<Target>& Targets() {
  static const std::vector<Target> targets = {
      {"thesis", "", "CRSH thesis (Reis 2015) tables 4.1-4.27: RAH and CRSH per level, totals, % of brute force, phase timings; Roger's quadtree beside them"},
      {"roger", "", "Roger et al. 2007 figures 9(a-c), 13(a-c): phase shares, work against the bunny's LOD, against cos(nx)cos(ny), tests per ray, against pixels; rah-quadtree and rah"},
      {"toczek", "", "Toczek et al. 2010 tables 1-2: traversed nodes per ray against the node order (table 1, bunny without ground) and against the triangle count (table 2: cubes, Suzanne, bunny, dragon); --algo tl"},
      {"thesis-ablation", "", "CRSH thesis: each faithful switch alone (cone test, hash layout and bits, shadow rule, one object, child merge) on SPONZA's 12 configurations, scored against tables 4.3-4.24"},
      {"hunt-mark", "", "Hunt and Mark 2008 tables 1-5: eye-ray and hard-shadow rates and build share against the triangle count (bunny LODs, conference), against Embree and the raster (tables 2-4), grid cells per soft-shadow ray, regular against 3D perspective grid (Sponza, conference); --algo grid"},
  };
  return targets;
}

const Target* FindTarget(const std::string& name) {
  for (const Target& t : Targets())
    if (t.name == name) return &t;
  return nullptr;
}

const std::vector<std::pair<int, int>>& ThesisShapes() {
  static const std::vector<std::pair<int, int>> shapes = {{8, 2}, {8, 3}, {8, 4}, {16, 2}, {16, 3}, {16, 4}};
  return shapes;
}

std::string Config::Canonical() const {
  // The quadtree's subdivision is 4 and its depth log2 of the image size: both follow from the size.
  const std::string shape = quadtree() ? "quadtree"
                            : embree() ? (primary ? "bvh primary=embree" : "bvh")
                            : grid()   ? fmt::format("grid{}{}{}", grid_area.empty() ? "" : " area=" + grid_area, primary ? " primary=grid" : "",
                                                   grid_regular_cells ? fmt::format(" regular-cells={}", grid_regular_cells) : "")
                            : tl()     ? fmt::format("lists={} order={}{}{}{}{}", lists, node_order, cull ? " cull=on" : "", heads.empty() ? "" : " heads=" + heads,
                                                   primary ? " primary=tl" : "", frustum ? " frustum=on" : "")
                                       : fmt::format("subdivision={} levels={}", subdivision, levels);
  // Faithful, object and path settings are appended only when set, so the keys of the other
  // configurations stay as they were. A preset is written as the switches it stands for: a preset
  // that gains a switch names other results.
  std::string faithful_text;
  if (!faithful.empty()) {
    faithful_text = " faithful=" + faithful + " [";
    for (const std::string& w : app::FaithfulPreset(faithful)) faithful_text += (faithful_text.back() == '[' ? "" : " ") + w;
    faithful_text += "]";
  }
  if (!switches.empty()) {
    faithful_text += " switches=[";
    for (const std::string& w : switches) faithful_text += (faithful_text.back() == '[' ? "" : " ") + w;
    faithful_text += "]";
  }
  if (one_object) faithful_text += " one-object";
  if (threads > 0) faithful_text += fmt::format(" threads={}", threads);
  return fmt::format("target={} scene={} file={} algo={} {} bounces={} size={}x{} objects=flat backend=emu{}{}", target, scene,
                     scene_file, algo, shape, bounces, width, height, path.empty() ? "" : " path=" + path, faithful_text);
}

std::string Config::Name() const {
  const std::string name = quadtree() ? fmt::format("{} {}", scene, algo)
                           : embree() ? fmt::format("{} embree{}", scene, primary ? " primary" : "")
                           : grid()   ? fmt::format("{} grid{}{}{}", scene, grid_area.empty() ? "" : " " + grid_area, primary ? " primary" : "",
                                                    grid_regular_cells ? fmt::format(" regular ~{}", grid_regular_cells) : "")
                           : tl()     ? fmt::format("{} tl K{} {}{}{}{}{}", scene, lists, node_order, cull ? " culled" : "", heads.empty() ? "" : " heads " + heads,
                                                  primary ? " primary" : "", frustum ? " frustum" : "")
                                      : fmt::format("{} {} s{} d{}", scene, algo, subdivision, levels);
  // roger measures one scene at several sizes (figure 13(c)); the thesis's run has one size.
  const std::string sized = target == "thesis" ? name : fmt::format("{} {}x{}", name, width, height);
  std::string with;
  for (const std::string& w : switches) with += " " + w;
  if (threads > 0) with += fmt::format(" threads {}", threads);
  return (faithful.empty() ? sized : sized + " faithful") + with;
}

std::string Config::RenderArgs() const {
  const std::string shape = quadtree() ? ""
                            : embree() ? (primary ? " --primary embree" : "")
                            : grid()   ? fmt::format("{}{}{}", grid_area.empty() ? "" : " --grid-area " + grid_area, primary ? " --primary grid" : "",
                                                   grid_regular_cells ? fmt::format(" --grid-regular-cells {}", grid_regular_cells) : "")
                            : tl()     ? fmt::format(" --lists {} --node-order {}{}{}{}{}", lists, node_order, cull ? " --backface-cull on" : "",
                                                   heads.empty() ? "" : " --polygon-heads " + heads, primary ? " --primary tl" : "",
                                                   frustum ? " --frustum-cull on" : "")
                                       : fmt::format(" --subdivision {} --levels {}", subdivision, levels);
  std::string faithful_args =
      faithful.empty() ? "" : fmt::format(" --faithful {}{}", faithful, one_object ? " --one-object" : "");
  for (const std::string& w : switches) faithful_args += " " + w;
  if (threads > 0) faithful_args += fmt::format(" --threads {}", threads);
  return fmt::format("scenes/{} --algo {}{} --bounces {} --objects flat --size {}x{}{}{} --no-oracle", scene_file, algo, shape,
                     bounces, width, height, path.empty() ? "" : " --path " + path, faithful_args);
}

const std::vector<std::vector<std::string>>& AblationSwitches() {
  // --shadow-bounces first changes nothing on SPONZA (one bounce, no mirror): not a variant.
  static const std::vector<std::vector<std::string>> variants = {
      {},
      {"--cone-test", "printed"},
      {"--cone-test", "printed-signed"},
      {"--hash-order", "polar-first"},
      {"--hash-bits", "8"},
      {"--hash-order", "polar-first", "--hash-bits", "8"},
      {"--shadow-rule", "lit"},
      {"--one-object"},
      {"--child-merge", "pairwise"},
      // The switches that alone gained cells on protocol 1's scene, together (the preset chosen there).
      {"--hash-order", "polar-first", "--hash-bits", "8", "--child-merge", "pairwise"},
      // The switches that alone gain cells against the defaults on the report's scene (protocol 2's:
      // docs/reproduce.md), together.
      {"--hash-bits", "8", "--child-merge", "pairwise"},
  };
  return variants;
}

std::vector<Config> AblationConfigs(const std::filesystem::path& scenes_dir, int width, int height) {
  std::vector<Config> configs;
  std::string current;
  for (const Config& base : ThesisConfigs(scenes_dir, width, height)) {
    if (base.scene != "SPONZA" || base.quadtree() || !base.faithful.empty()) continue;
    current = base.scene_file;
    for (const std::vector<std::string>& v : AblationSwitches()) {
      Config c = base;
      c.target = "thesis-ablation";
      c.switches = v;
      configs.push_back(c);
    }
  }
  // Every other committed fit's scene, under the defaults and the last variant (the switches that
  // alone gain cells, together), to score the fits side by side out of sample.
  const std::size_t first = configs.size();
  for (const SceneChoice& sc : ThesisScenes())
    for (const SceneFile& f : sc.files)
      if (FitProtocolOfScene(f.file) > 0 && f.file != current && std::filesystem::exists(scenes_dir / f.file))
        for (std::size_t i = 0; i < first; ++i)
          if (configs[i].switches.empty() || configs[i].switches == AblationSwitches().back()) {
            Config c = configs[i];
            c.scene_file = f.file;
            configs.push_back(c);
          }
  return configs;
}

std::vector<Config> ThesisConfigs(const std::filesystem::path& scenes_dir, int width, int height) {
  std::vector<Config> configs;
  for (const SceneChoice& s : ThesisScenes()) {
    Config c;
    c.scene = s.paper;
    c.scene_file = s.files.back().file;
    for (const SceneFile& f : s.files)
      if (std::filesystem::exists(scenes_dir / f.file)) {
        c.scene_file = f.file;
        break;
      }
    c.bounces = s.bounces;
    c.width = width;
    c.height = height;
    for (const auto& [sub, depth] : ThesisShapes())
      for (const char* algo : {"rah", "crsh"}) {
        c.algo = algo;
        c.subdivision = sub;
        c.levels = depth;
        configs.push_back(c);
      }
    c.algo = "rah-quadtree";
    c.subdivision = 4;
    c.levels = 0;
    configs.push_back(c);
  }
  // The same shapes with the thesis's method as printed, beside rayspace's defaults.
  const std::size_t defaults = configs.size();
  for (std::size_t i = 0; i < defaults; ++i) {
    Config c = configs[i];
    if (c.quadtree()) continue;
    c.faithful = "thesis";
    for (const SceneChoice& s : ThesisScenes())
      if (s.paper == c.scene) c.one_object = s.one_object;
    configs.push_back(c);
  }
  return configs;
}

}  // namespace rayspace::reproduce
