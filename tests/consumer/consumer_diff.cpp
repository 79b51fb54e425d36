// consumer_diff SCENE GOOD_KERNEL BAD_KERNEL: diffs both kernels for the reduce pass through the
// library API, and renders with them; exit 0 when the good one is equal and renders the emulator's
// frame, and the bad one diverges first in reduce and its render fails.
#include <cstdio>
#include <exception>
#include <string>

#include "rayspace/api.h"

namespace api = rayspace::api;

api::DiffReport DiffReduce(const char* scene, const char* kernel) {
  api::DiffRequest request;
  request.frame.scene = scene;
  request.frame.size = "48x48";
  request.kernels.push_back({"reduce", kernel});
  return api::Diff(request);
}

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: consumer_diff SCENE GOOD_KERNEL BAD_KERNEL\n");
    return 2;
  }
  try {
    std::printf("%s\n", api::Version().c_str());
    const api::DiffReport good = DiffReduce(argv[1], argv[2]);
    const api::DiffReport bad = DiffReduce(argv[1], argv[3]);
    std::size_t reduce_calls = 0;
    for (const api::PassCall& c : good.calls) reduce_calls += c.pass == "reduce";
    const api::PassCall* first_bad = nullptr;
    for (const api::PassCall& c : bad.calls)
      if (!c.equal && !first_bad) first_bad = &c;
    std::printf("good kernel: %s (%zu calls, %zu of reduce)\n", api::ToString(good.verdict), good.calls.size(), reduce_calls);
    std::printf("bad kernel: %s, first divergent pass '%s' at %s: %s\n", api::ToString(bad.verdict), bad.first_divergent_pass.c_str(),
                first_bad ? first_bad->label.c_str() : "-", first_bad ? first_bad->first_mismatch.c_str() : "-");
    const bool ok = good.verdict == api::Verdict::kEqual && reduce_calls > 0 && bad.verdict == api::Verdict::kDivergent &&
                    bad.first_divergent_pass == "reduce" && first_bad && !first_bad->first_mismatch.empty() &&
                    good.json.find("\"equal\": true") != std::string::npos;
    // A frame rendered on the device with the good kernel is the emulator's frame, bit for bit; the bad
    // kernel's frame stops with a device output error.
    api::RenderRequest render;
    render.frame.scene = argv[1];
    render.frame.size = "48x48";
    render.path = "passes";
    const api::RenderReport emu = api::Render(render);
    render.backend = "vulkan";
    render.kernels.push_back({"reduce", argv[2]});
    const api::RenderReport device = api::Render(render);
    bool bad_refused = false;
    try {
      render.kernels[0].file = argv[3];
      api::Render(render);
    } catch (const std::exception& e) {
      bad_refused = std::string(e.what()).find("reduce") != std::string::npos;
      std::printf("bad kernel's render: %s\n", e.what());
    }
    std::printf("render: emu %s, vulkan with the good kernel %s (%zu oracle mismatches, %zu bytes)\n", emu.digest.c_str(),
                device.digest.c_str(), device.oracle_mismatches, device.rgb.size());
    const bool rendered = !emu.digest.empty() && emu.digest == device.digest && device.oracle_mismatches == 0 &&
                          device.rgb.size() == 48u * 48u * 3u && device.rgb == emu.rgb && bad_refused &&
                          device.statistics.find("\"rays\"") != std::string::npos;
    std::printf("%s\n", ok && rendered ? "verdicts as expected" : "UNEXPECTED VERDICTS");
    return ok && rendered ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer_diff: %s\n", e.what());
    return 1;
  }
}
