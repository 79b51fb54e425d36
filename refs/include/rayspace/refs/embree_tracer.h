// Embree 3 as an independent tracer: the oracle that re-traces the emulator's secondary rays.
// Configuration is fixed and reported: ISA sse4.2 (available on every x86-64 machine this runs on,
// so results do not change with the host's vector width), build quality high, robust scene flag.
#pragma once
#include <memory>

#include "rayspace/emu/tracer.h"

namespace rayspace::refs {

std::unique_ptr<Tracer> MakeEmbreeTracer(const SceneBuffers& scene, int threads);

}  // namespace rayspace::refs
