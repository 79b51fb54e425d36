// Procedural geometry for self-contained scenes. Each generator returns sub-meshes in object space
// with analytic vertex normals; the scene's transform places them.
#pragma once
#include <cstddef>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "rayspace/scene.h"

namespace rayspace {

// Builds the generator named `kind` from its JSON parameters. `where` names the scene file and
// object for error messages ("scene.json: objects[3]"). Unknown generators or bad parameters throw
// InputError. The generators and their parameters are listed in docs/scene-format.md.
MeshData Generate(const std::string& kind, const nlohmann::json& params, const std::string& where);

// The individual generators (object space, one sub-mesh unless stated).
// Axis-aligned box centred at the origin, each face split into n x n quads; inward normals when asked.
MeshData GenerateBox(glm::vec3 size, int subdivisions, bool inward, const std::string& name);
// UV sphere: `segments` around the axis (Y), `rings` from pole to pole.
MeshData GenerateSphere(float radius, int segments, int rings, const std::string& name);
// Cylinder along Y from 0 to height, optional caps.
MeshData GenerateCylinder(float radius, float height, int segments, bool caps, const std::string& name);
// Height field y = amplitude * cos(frequency x) * cos(frequency z) over a size x size square.
MeshData GenerateWavy(float size, float amplitude, float frequency, int resolution, const std::string& name);
// The Cornell box room (published measurements, millimetres): floor, ceiling, back, front, left and
// right walls as six sub-meshes facing inward, each split n x n. `closed` = false leaves out the front.
MeshData GenerateCornellRoom(int subdivisions, bool closed);

// Generators refuse parameters that would make this many triangles or more.
inline constexpr std::size_t kMaxGeneratedTriangles = 4'000'000;

// Office furniture, one sub-mesh each, object space in metres: standing on y = 0, centred on the
// Y axis, front (where a person sits or looks from) towards +Z. Built from boxes split
// detail x detail per face (12 detail^2 triangles each) and capped cylinders with 8 detail
// segments (32 detail triangles each), so a piece with B boxes and C cylinders has
// 12 detail^2 B + 32 detail C triangles.
// Desk 1.40 x 0.75 x 0.70 with a drawer pedestal: B = 3, C = 4.
MeshData GenerateDesk(int detail, const std::string& name);
// Swivel office chair facing +Z, seat at 0.47, five-star base on casters: B = 8, C = 6.
MeshData GenerateChair(int detail, const std::string& name);
// Open bookcase 0.90 x 1.90 x 0.35 with four compartments of books: B = 28, C = 0.
MeshData GenerateShelf(int detail, const std::string& name);
// Flat-panel monitor on a round foot, screen facing +Z: B = 2, C = 1.
MeshData GenerateMonitor(int detail, const std::string& name);
// Desk lamp: round foot, upright, arm reaching towards +Z, cylindrical shade: B = 1, C = 3.
MeshData GenerateLamp(int detail, const std::string& name);

// Parameters of Generate(), all optional (default in brackets):
//   box          size [1] number or [x,y,z] > 0; subdivisions [1] 1..1024; inward [false]
//   sphere       radius [1] > 0; segments [32] 3..4096; rings [16] 2..4096
//   cylinder     radius [0.5] > 0; height [1] > 0; segments [32] 3..4096; caps [true]
//   wavy         size [1] > 0; amplitude [0.05] >= 0; frequency [10] >= 0; resolution [32] 1..4096
//   cornell_room subdivisions [1] 1..1024; closed [true]
//   desk, chair, shelf, monitor, lamp   detail [2] 1..64
// Lengths are at most 1e6. Triangle counts: box 12 n^2, sphere 2 segments (rings - 1),
// cylinder 2 segments (+ 2 segments with caps), wavy 2 resolution^2, cornell_room 2 n^2 per wall.

}  // namespace rayspace
