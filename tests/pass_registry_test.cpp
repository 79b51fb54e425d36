// The pass registry against the emulator side: the diff's pass table runs exactly the registered
// calls, each call's pass is a registered pass, frame labels resolve to their pass, and the timing
// table's thesis phases come from the registry. (gpu/tests/registry_test.cpp holds the kernels to it.)
#include <doctest/doctest.h>

#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "rayspace/pass_registry.h"
#include "rayspace/verify/pass_table.h"

namespace rayspace {
namespace {

TEST_CASE("registry: the diff's pass table runs exactly the registered calls") {
  std::set<std::string> registered, table;
  for (const PassSpec& p : kPasses)
    for (const CallSpec& c : p.calls) registered.insert(std::string(c.name));
  for (const verify::PassMethod& m : verify::PassMethods()) {
    INFO("pass table method ", m.method);
    CHECK(table.insert(m.method).second);
    CHECK(registered.count(m.method) == 1);
  }
  for (const std::string& c : registered) {
    INFO("registered call ", c);
    CHECK(table.count(c) == 1);
  }
}

TEST_CASE("registry: every call reports a registered pass that lists it") {
  for (const verify::PassMethod& m : verify::PassMethods()) {
    std::vector<verify::BufferSet> inputs(1);
    if (m.method == "raygen") {  // the ray kind selects the pass
      inputs.resize(3);
      for (std::uint32_t k = 0; k < 3; ++k) inputs[k].scalars["kind"] = k;
    }
    for (const verify::BufferSet& in : inputs) {
      const std::string pass = m.pass(in);
      INFO("call ", m.method, " -> pass ", pass);
      const std::optional<PassId> id = FindPass(pass);
      REQUIRE(id.has_value());
      bool listed = false;
      for (const CallSpec& c : Pass(*id).calls) listed = listed || c.name == m.method;
      CHECK(listed);
    }
  }
}

TEST_CASE("registry: frame labels resolve to their pass, and only to registered ones") {
  CHECK(PassOfLabel("traverse.L2.shadow.b0") == PassId::kTraverse);
  CHECK(PassOfLabel("traverse.objects.reflection.b1") == PassId::kTraverse);
  CHECK(PassOfLabel("traverse.compact.L2.shadow.b0") == PassId::kTraverseCompact);  // the longer name wins
  CHECK(PassOfCall("traverse.compact.level") == PassId::kTraverseCompact);
  CHECK(PassOfLabel("raygen.shadow.b0") == PassId::kRaygenShadow);
  CHECK(PassOfLabel("surfaces.hits.reflection.b1") == PassId::kSurfacesHits);  // the longer name wins
  CHECK(PassOfLabel("surfaces") == PassId::kSurfaces);
  CHECK(PassOfLabel("sorted.b0") == std::nullopt);  // a prefix must end at a dot
  CHECK(PassOfLabel("prep") == std::nullopt);
  CHECK(FindPass("intersect") == PassId::kIntersect);
  CHECK(FindPass("intersects") == std::nullopt);
  for (const PassSpec& p : kPasses) CHECK(Pass(p.id).name == p.name);
}

TEST_CASE("registry: thesis phases are the timing table's") {
  const std::set<std::string_view> phases = {"",
                                             "ray_creation",
                                             "ray_compression",
                                             "ray_sorting",
                                             "ray_decompression",
                                             "hierarchy_creation",
                                             "hierarchy_traversal",
                                             "final_intersection_tests"};
  for (const PassSpec& p : kPasses) {
    INFO("pass ", std::string(p.name));
    CHECK(phases.count(p.thesis_phase) == 1);
  }
}

TEST_CASE("registry: every planted fault has a diff case that must catch it in its own pass") {
  // tests/cli_diff.cmake runs each fault in the ctest cli.diff.fault.[<algo>.]<pass>:<n> or in a list
  // of cli.diff.faults.<group> (a frame each), a workgroup fault by its name on both sides,
  // <pass>:<name> and <pass>:<name>@emu, and a fault the emulated kernel mirrors as <pass>:<n>@emu too.
  std::ifstream in(std::string(RAYSPACE_SOURCE_DIR) + "/tests/cli_diff.cmake");
  REQUIRE(in.good());
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const PassSpec& p : kPasses)
    for (const FaultSpec& f : p.faults) {
      const std::string id = std::string(p.name) + ":" + (f.name.empty() ? std::to_string(f.number) : std::string(f.name));
      INFO("fault ", id, " (", std::string(f.effect), ")");
      CHECK(text.find(id) != std::string::npos);
      // A named (workgroup) fault is in the list whose every entry runs on both sides.
      if (!f.name.empty()) CHECK(text.find("checker_case(fault.${f}@emu") != std::string::npos);
      // A pass's own fault its emulated kernel mirrors runs on the emulator's side too, caught in its pass.
      if (f.emu) CHECK(text.find(id + "@emu") != std::string::npos);
    }
}

TEST_CASE("registry: docs/architecture.md maps exactly the registered passes to their kernels and files") {
  std::ifstream in(std::string(RAYSPACE_SOURCE_DIR) + "/docs/architecture.md");
  REQUIRE(in.good());
  std::set<std::string> documented;
  std::string line;
  bool in_map = false;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) in_map = line == "## Passes and files";
    if (!in_map || line.rfind("| `", 0) != 0) continue;
    // | `pass` | `gpu/shaders/kernel.comp`... | `emulator file` | `host file` |
    std::vector<std::string> paths;
    for (std::size_t a = line.find('`'); a != std::string::npos; a = line.find('`', line.find('`', a + 1) + 1))
      paths.push_back(line.substr(a + 1, line.find('`', a + 1) - a - 1));
    REQUIRE(paths.size() >= 4);
    const std::string pass = paths[0];
    INFO("docs row ", line);
    const std::optional<PassId> id = FindPass(pass);
    REQUIRE(id.has_value());
    CHECK(documented.insert(pass).second);
    const PassSpec& p = Pass(*id);
    const std::string kernel = "gpu/shaders/" + std::string(p.kernel) + (p.graphics ? ".vert" : ".comp");
    CHECK(paths[1] == kernel);
    // Same file name on each backend: emu/src/<family>.cpp and gpu/src/<family>.cpp, where the family
    // is the kernel's name up to its first '_'.
    const std::string family = std::string(p.kernel.substr(0, p.kernel.find('_')));
    CHECK(paths[paths.size() - 2] == "emu/src/" + family + ".cpp");
    CHECK(paths[paths.size() - 1] ==
          (p.push_type == "ElementwisePush" ? std::string("gpu/src/elementwise.cpp") : "gpu/src/" + family + ".cpp"));
    // The family's tests: tests/<family>_test.cpp.
    CHECK(std::ifstream(std::string(RAYSPACE_SOURCE_DIR) + "/tests/" + family + "_test.cpp").good());
    for (std::size_t k = 1; k < paths.size(); ++k) {
      if (paths[k].find('/') == std::string::npos) continue;  // "raster.frag" beside its .vert
      INFO("file ", paths[k]);
      CHECK(std::ifstream(std::string(RAYSPACE_SOURCE_DIR) + "/" + paths[k]).good());
    }
  }
  for (const PassSpec& p : kPasses) {
    INFO("registered pass ", std::string(p.name));
    CHECK(documented.count(std::string(p.name)) == 1);
  }
}

}  // namespace
}  // namespace rayspace
