// rayspace's library API: what a kernel developer's own program or test calls to render a frame on a
// backend, with kernels of theirs, and to diff them against the emulator pass by pass, reading each
// result as a value. `rayspace render` and `rayspace diff` are these calls with their outputs printed
// and written; docs/library.md shows them in use.
//
// Every call is self-contained: its configuration travels in the request, and a bad request (an
// unknown pass, a kernel that does not compile or breaks the pass's contract, a scene that does not
// load) throws rayspace::InputError naming the input; a failing driver throws std::runtime_error.
// A call prints its summary (a render's statistics, a diff's pass table) on stdout, as the command does.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace rayspace::api {

// The install whose kernel includes a user's .comp file compiles against. The CMake package defines
// RAYSPACE_INSTALL_PREFIX for its consumers (find_package(rayspace)); empty: the install holding the
// running executable, else the source tree rayspace was built from.
#ifdef RAYSPACE_INSTALL_PREFIX
inline const char* const kInstallPrefix = RAYSPACE_INSTALL_PREFIX;
#else
inline const char* const kInstallPrefix = "";
#endif

// One frame: the scene and its tracer. The defaults are `rayspace diff`'s.
struct FrameConfig {
  std::string scene;           // a scene file: .json (bundled or the user's), .obj, .ply
  std::string data;            // the data root for a scene that names models in it ("": none)
  std::string size = "64x64";  // WxH
  std::string algo = "crsh";   // crsh, rah, rah-quadtree, tl, grid, brute, embree
  int bounces = -1;            // -1: the scene's own
  int local_size = 64;         // the compute kernels' workgroup size (a diff's; a render runs 64)
};

// A user's kernel in place of the built-in kernel of one pass: a .comp file (compiled with the
// install's includes) or a .spv file, checked against the pass's contract before anything runs.
struct KernelOverride {
  std::string pass;  // e.g. "reduce", "trim" (`rayspace diff --help` lists them)
  std::string file;
};

struct DiffRequest {
  FrameConfig frame;
  std::string backends = "emu,vulkan";  // expected,actual: emu,vulkan, emu,sim or sim,vulkan
  std::vector<KernelOverride> kernels;
  std::string compare = "auto";         // auto, bitwise or relaxed (docs/numerics.md)
  std::string inject;                   // a planted fault (`rayspace diff --inject`), "" for none
  std::string prefix = kInstallPrefix;  // see kInstallPrefix
};

enum class Verdict {
  kEqual,          // every pass call equal (or, relaxed, within what a conformant device may compute)
  kDivergent,      // a pass call differs
  kCheckerStopped,  // a workgroup or simulator checker found a fault of a kernel and stopped the frame
  kBackendFailed    // the device could not finish a pass (a failed Vulkan call, the simulator's
                    // step limit): nothing was compared from that pass on
};
const char* ToString(Verdict v);

// One call of a pass in the frame, compared.
struct PassCall {
  std::string pass;   // the pass (`diff --inject` and `--kernel` name it so)
  std::string label;  // where in the frame, e.g. "reduce.L2.shadow.b0"
  bool equal = true;
  bool within_spec = false;    // differs only as a conformant device may (relaxed comparison)
  std::string first_mismatch;  // "" when equal: "BUFFER[INDEX]: expected E, actual A (M of N elements differ)"
};

struct DiffReport {
  Verdict verdict = Verdict::kEqual;
  std::string first_divergent_pass;  // "" when none diverged
  std::string stopped;               // why the frame stopped early, "" when it ran to the end
  std::vector<PassCall> calls;
  std::string json;  // the whole report, as `rayspace diff --report FILE` writes it (docs/verification.md)
};

// Runs the frame with every pass on both backends (each pass on the actual backend's previous
// outputs) and compares every output.
DiffReport Diff(const DiffRequest& request);

struct RenderRequest {
  FrameConfig frame;
  std::string backend = "emu";  // emu, vulkan or sim (the simulated GPU)
  std::string path = "auto";    // hierarchy traversal: fused, passes (traverse then reduce), or auto
  std::vector<KernelOverride> kernels;  // vulkan and sim only
  bool oracle = true;                   // re-trace every ray with Embree and compare the hits
  std::string prefix = kInstallPrefix;  // see kInstallPrefix
};

struct RenderReport {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;       // 8-bit sRGB, three bytes a pixel, rows from the top
  std::string digest;                   // the frame's digest: equal digests, equal frames
  std::size_t oracle_mismatches = 0;    // rays whose hit the oracle disagrees with (0 without it)
  std::string statistics;               // the statistics JSON, as `rayspace render --stats` writes it
};

// Renders one frame on the backend, with the user's kernels in place of built-in ones.
RenderReport Render(const RenderRequest& request);

// "rayspace X.Y.Z", as `rayspace --version` prints first.
std::string Version();

}  // namespace rayspace::api
