// Buffer layouts and constants shared by the emulated passes (C++) and the GLSL kernels.
// Valid GLSL (std430 blocks use these structs) and valid C++ (GLM mirrors the GLSL types).
// Every struct is a multiple of 16 bytes so arrays of it have the same stride in both languages.
#ifndef RAYSPACE_LAYOUT_H
#define RAYSPACE_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace rayspace::layout {
using uint = std::uint32_t;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
#define RS_CONST(type, name, value) inline constexpr type name = value
#else
#define RS_CONST(type, name, value) const type name = value
#endif

// Primitive id of an empty pixel / a ray that hit nothing.
RS_CONST(uint, kNoPrim, 0xFFFFFFFFu);
// Ray kinds (Ray.kind).
RS_CONST(uint, kRayShadow, 0u);
RS_CONST(uint, kRayReflection, 1u);
RS_CONST(uint, kRayRefraction, 2u);
RS_CONST(uint, kRayPrimary, 3u);  // eye rays, traced beside the raster (--primary tl)
// Fixed-point scale of the colour accumulator: integer adds make the sum independent of the order in
// which contributions arrive (GPU atomics), so the image is deterministic.
RS_CONST(float, kAccumScale, 4294967296.0);  // 2^32
RS_CONST(float, kAccumMax, 65535.0);         // contributions are clamped to [0, kAccumMax]
// Arrays that may outgrow one storage binding (maxStorageBufferRange) are bound as this many
// consecutive bindings ("pages"); see gpu/shaders/paged.glsl.
RS_CONST(uint, kBufferPages, 4u);
// Shininess exponents are integers in [0, kMaxShininess] (pow by repeated squaring; no pow()).
RS_CONST(uint, kMaxShininess, 4096u);

// One triangle's vertex positions in world space (w = 1).
struct Triangle {
  vec4 v0;
  vec4 v1;
  vec4 v2;
};

// Vertex normals of one triangle (w = 0); the face normal when the mesh has none.
struct TriangleNormals {
  vec4 n0;
  vec4 n1;
  vec4 n2;
};

// x: material index, y: object (sub-mesh) index.
struct TriangleInfo {
  uvec4 ids;
};

struct Material {
  vec4 diffuse_reflectivity;   // rgb diffuse, a reflectivity in [0,1]
  vec4 specular_shininess;     // rgb specular, a integer shininess exponent
  vec4 transparency_ior;       // x transparency in [0,1], y index of refraction
};

// Light shapes (Light.sampling.x). A point light has one sample, its position; an area light has
// `samples` points per shading point, drawn by the stratified sampler of rayspace/kernel_functions.h
// (docs/area-lights.md).
RS_CONST(uint, kLightPoint, 0u);
RS_CONST(uint, kLightRect, 1u);    // centre + x axis_u + y axis_v, x, y in [-1, 1)
RS_CONST(uint, kLightDisk, 2u);    // centre + r cos(phi) axis_u + r sin(phi) axis_v, r <= 1
RS_CONST(uint, kLightSphere, 3u);  // centre + radius (x, y, z), a point of the unit sphere
// The most samples of one light and of all lights together (shadow slots per shading point).
RS_CONST(uint, kMaxLightSamples, 256u);
RS_CONST(uint, kMaxShadowSlots, 1024u);

struct Light {
  vec4 position;               // xyz centre, w sphere radius
  vec4 color_intensity;        // rgb colour, a intensity
  vec4 attenuation;            // x constant, y linear, z quadratic, w 1 / samples
  vec4 axis_u;                 // xyz first half-axis (rect, disk), w 1 / strata columns
  vec4 axis_v;                 // xyz second half-axis (rect, disk), w 1 / strata rows
  uvec4 sampling;              // x shape, y samples, z first shadow slot, w strata columns
};

// A secondary ray. Shadow rays start at the light (thesis eq. 3.1) and end just before the surface.
struct Ray {
  vec4 origin_tmin;            // xyz origin, w smallest accepted t
  vec4 direction_tmax;         // xyz direction, w largest accepted t
  uvec4 info;                  // x pixel, y primitive to ignore (the surface it leaves), z kind,
                               // w light index (shadow; an area light's samples share it) or
                               // surface slot (reflection, refraction)
  vec4 weight;                 // rgb path weight (product of reflectivity / transparency), a unused
};

// A shading point: a G-buffer pixel (generation 0) or the hit of a reflection/refraction ray.
struct Surface {
  vec4 position;               // xyz, w 1 when valid, 0 when the slot is empty
  vec4 normal;                 // xyz interpolated shading normal (unit, not face-forwarded)
  vec4 incoming;               // xyz unit direction of the ray that arrived here
  vec4 weight;                 // rgb path weight
  uvec4 info;                  // x primitive, y pixel, z material
};

// A node of the ray-space hierarchy: a sphere holding the origins of its rays and a cone holding their
// directions (half-angle alpha in [0, pi], kept as cos and sin so no kernel needs trigonometry).
struct ConeNode {
  vec4 sphere;                 // xyz centre, w radius
  vec4 cone;                   // xyz unit axis, w cos(alpha)
  vec4 extra;                  // x sin(alpha), y number of rays below, zw unused
};

// Per-frame constants computed on the host in double and rounded once to float.
struct FrameConstants {
  mat4 view_proj;              // world -> Vulkan clip space (y down, z in [0, w])
  vec4 eye;                    // xyz camera position
  vec4 pixel_origin;           // direction to the centre of pixel (0, 0)
  vec4 pixel_dx;               // direction step per pixel in x
  vec4 pixel_dy;               // direction step per pixel in y
  vec4 scene_lo;               // scene bounding box
  vec4 scene_hi;
  vec4 params;                 // x ray epsilon (absolute), y depth scale (1/far), z shadow tmax factor
  uvec4 dims;                  // x width, y height, z triangles, w lights
};

#ifdef __cplusplus
static_assert(sizeof(Triangle) == 48);
static_assert(sizeof(TriangleNormals) == 48);
static_assert(sizeof(TriangleInfo) == 16);
static_assert(sizeof(Material) == 48);
static_assert(sizeof(Light) == 96);
static_assert(sizeof(Ray) == 64);
static_assert(sizeof(Surface) == 80);
static_assert(sizeof(ConeNode) == 48);
static_assert(sizeof(FrameConstants) == 64 + 8 * 16);
static_assert(offsetof(Ray, info) == 32);
static_assert(offsetof(FrameConstants, dims) == 176);
}  // namespace rayspace::layout
#endif
// RS_CONST stays defined: rayspace/contract.h declares the rest of the kernel contract with it.
#endif  // RAYSPACE_LAYOUT_H
