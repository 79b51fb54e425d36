// What `rayspace reproduce` measures: its targets, and each target's configurations (scene, tracer,
// hierarchy shape, frame size), each with a canonical text that, with the scene's content and the
// version, names its result.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rayspace::reproduce {

// A scene file that stands in for a paper's scene, and how it differs, for the report's rows.
struct SceneFile {
  std::string file;  // relative to the scenes directory
  std::string note;
};
// A paper's scene and the scene files that stand in for it. The first of `files` found in the scenes
// directory is used, so a closer stand-in takes over when it is added.
struct SceneChoice {
  std::string paper;             // the thesis's name: OFFICE, CORNELL, SPONZA
  std::vector<SceneFile> files;  // candidates, best first
  int bounces = 1;               // --bounces: reflection bounces the thesis's frame traces
  bool one_object = false;       // the thesis's model is one object: --one-object in faithful runs
};
// The fitted protocol whose SPONZA scene (`reproduce thesis --fit`, committed under scenes/ as
// sponza-thesis-fit.json, -2.json, ...) `scene_file` is; 0 for any other file.
int FitProtocolOfScene(const std::string& scene_file);
// The thesis's scenes, the one table to change when a scene's stand-in changes.
const std::vector<SceneChoice>& ThesisScenes();

struct Target {
  std::string name;
  std::string skip_reason;  // empty: implemented
  std::string what;         // one line for --list
};
const std::vector<Target>& Targets();
const Target* FindTarget(const std::string& name);

struct Config {
  std::string target = "thesis";
  std::string scene;       // the paper's name
  std::string scene_file;  // relative to the scenes directory
  std::string algo;        // crsh, rah, rah-quadtree
  int subdivision = 8, levels = 2, bounces = 1;
  int width = 512, height = 512;
  std::string faithful;    // empty, or a --faithful preset (the thesis's method as printed)
  // thesis-ablation: render switches of the faithful family (--cone-test printed, ...) given one by one.
  std::vector<std::string> switches;
  bool one_object = false;  // --one-object
  // --path: empty for render's default (fused: each level tests and compacts in one pass); "passes"
  // runs the cone-sphere tests and the stream reduction as separate passes, timed apart (roger).
  std::string path;
  // --algo tl: the lists and their order (toczek); 0 and empty for the hierarchy's tracers.
  std::uint32_t lists = 0;
  std::string node_order;
  bool cull = false;  // --algo tl --backface-cull on
  std::string heads;  // --algo tl --polygon-heads: empty for off
  // --primary tl (eye rays traced through the lists beside the raster) and --frustum-cull on.
  bool primary = false, frustum = false;
  // --algo grid (hunt-mark): --grid-area (empty: the default), and `primary` is --primary grid.
  std::string grid_area;
  // --grid-regular-cells (0: not given, the regular grid is 54 along the longest side).
  std::uint64_t grid_regular_cells = 0;
  // The frame's worker threads (hunt-mark's thread scaling); 0: the run's (cores / --jobs).
  int threads = 0;
  bool grid() const { return algo == "grid"; }
  bool tl() const { return algo == "tl"; }
  bool quadtree() const { return algo == "rah-quadtree"; }
  bool embree() const { return algo == "embree"; }  // hunt-mark's BVH beside the grids (`primary`: --primary embree)
  // Every setting that changes the counts, as one line (part of the result's key).
  std::string Canonical() const;
  // Short, for progress lines and tables: "OFFICE crsh s8 d2".
  std::string Name() const;
  // The equivalent `rayspace render` arguments.
  std::string RenderArgs() const;
};

// The thesis's configurations at width x height: per scene, 6 shapes x {rah, crsh}, then Roger's
// quadtree; then, per scene, the 6 shapes x {rah, crsh} again with --faithful thesis.
// Scene files are resolved in `scenes_dir`.
std::vector<Config> ThesisConfigs(const std::filesystem::path& scenes_dir, int width, int height);

// thesis-ablation: SPONZA's 12 default configurations (6 shapes x {rah, crsh}) under rayspace's
// defaults and under each faithful switch alone (AblationSwitches), at width x height.
std::vector<Config> AblationConfigs(const std::filesystem::path& scenes_dir, int width, int height);
// The switches the ablation varies, one variant each; the first, empty, is rayspace's defaults.
const std::vector<std::vector<std::string>>& AblationSwitches();

// The hierarchy shapes of the thesis's tables, in table order.
const std::vector<std::pair<int, int>>& ThesisShapes();

}  // namespace rayspace::reproduce
