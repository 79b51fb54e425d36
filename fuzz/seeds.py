#!/usr/bin/env python3
"""Writes the seed corpora of the numeric harnesses (fuzz/corpus/<harness>/) in the documented
float32 layouts (fuzz/README.md), a few scene files for scene_load and SPIR-V modules for spirv_load. Run from anywhere; the
output is committed, so this only needs rerunning to add seeds."""
import gzip
import math
import os
import shutil
import struct
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def write(harness, name, floats=None, raw=None):
    d = os.path.join(HERE, "corpus", harness)
    os.makedirs(d, exist_ok=True)
    data = raw if raw is not None else struct.pack("<%df" % len(floats), *floats)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


PI = math.pi
HUGE, TINY, DENORM = 2.0 ** 60, 2.0 ** -60, 1e-40
nodes = {
    "unit": [0, 0, 0, 1, 0, 0, 1, 0.3],
    "point_ray": [1, 2, 3, 0, 0, 1, 0, 0],
    "half_space": [0, 0, 0, 0.5, 0, 0, 1, PI / 2],
    "near_half": [0, 0, 0, 0.5, 1, 1, 0, PI / 2 - 1e-6],
    "wide": [0, 0, 0, 2, 0, 0, -1, 3.0],
    "full": [0, 0, 0, 1, 1, 0, 0, PI],
    "tiny_angle": [5, 5, 5, 0, 0.3, 0.4, 0.5, 1e-7],
    "huge": [HUGE, -HUGE, HUGE, HUGE, 1, 2, 3, 0.7],
    "tiny": [TINY, TINY, -TINY, TINY, 3, 2, 1, 0.7],
    "denormal": [DENORM, 0, 0, DENORM, 0, 1, 0, 0.1],
}
pairs = [("unit", "unit"), ("unit", "point_ray"), ("half_space", "near_half"), ("wide", "tiny_angle"),
         ("full", "unit"), ("huge", "tiny"), ("denormal", "point_ray")]
for a, b in pairs:
    write("cone_union", f"{a}-{b}", nodes[a] + nodes[b])
# antiparallel and nearly antiparallel axes
write("cone_union", "antiparallel", [0, 0, 0, 1, 0, 0, 1, 0.1] + [0, 0, 0, 1, 0, 0, -1, 0.1])
write("cone_union", "near_antiparallel", [0, 0, 0, 1, 0, 0, 1, 0.1] + [0, 0, 0, 1, 1e-7, 0, -1, 0.1])
write("cone_union", "same_axis_zero_angles", [0, 0, 0, 0, 0, 0, 1, 0] + [1, 0, 0, 0, 0, 0, 1, 0])

rays = {
    "along_axis": [0, 0, 0, 0, 0, 1],
    "against_axis": [0, 0, 0, 0, 0, -1],
    "perpendicular": [1, 1, 1, 1, 0, 0],
    "grazing": [0, 0, 0, 1, 0, 1],
    "far": [HUGE, 0, 0, 0, 1, 0],
    "tiny": [TINY, 0, 0, 0, TINY, 1],
}
for n in ["unit", "point_ray", "half_space", "tiny_angle", "huge", "wide"]:
    for r in rays:
        write("cone_grow", f"{n}-{r}", nodes[n] + rays[r])

spheres = {
    "on_surface": [1, 0, 1, 0],
    "behind_apex": [0, 0, -5, 4.9],
    "at_apex": [0, 0, 0, 0],
    "far": [HUGE, HUGE, HUGE, 1],
    "touching": [3, 0, -4, 4],
    "tiny": [TINY, 0, TINY, 0],
}
cone45 = [0, 0, 0, 0, 0, 0, 1, PI / 4]
for s in spheres:
    write("cone_sphere", f"cone45-{s}", cone45 + spheres[s])
    write("cone_sphere", f"half_space-{s}", nodes["half_space"] + spheres[s])
    write("cone_sphere", f"tiny_angle-{s}", nodes["tiny_angle"] + spheres[s])

# cone_cull: node, eps, then up to 32 spheres (one group); the harness also slides the group to the
# edge of culling, so a seed needs only a shape and a direction.
def cluster(centre, spread, radius, n):
    out = []
    for i in range(n):
        a, b = 2.399963 * i, (i + 0.5) / n  # a deterministic spiral
        out += [centre[0] + spread * math.cos(a) * b, centre[1] + spread * math.sin(a) * b,
                centre[2] + spread * (2 * b - 1), radius * (1 + i % 3) / 3]
    return out


for name, node, eps, group in [
        ("narrow-offaxis", nodes["tiny_angle"], 0, cluster([50, -20, 5], 1, 0.1, 32)),
        ("unit-behind", nodes["unit"], 0, cluster([0, 0, -10], 2, 0.5, 16)),
        ("half_space-side", nodes["half_space"], 1e-3, cluster([0, 10, -3], 0.5, 0, 8)),
        ("near_half-below", nodes["near_half"], 0, cluster([1, -1, -5], 3, 1, 32)),
        ("wide-one", nodes["wide"], 0, cluster([0, 0, 20], 0, 1, 1)),
        ("full", nodes["full"], 0, cluster([9, 9, 9], 1, 1, 4)),
        ("huge", nodes["huge"], 2.0 ** 40, cluster([-HUGE, HUGE, 0], 2.0 ** 50, 2.0 ** 40, 12)),
        ("tiny", nodes["tiny"], 0, cluster([-TINY, TINY, 3 * TINY], TINY / 4, 0, 7)),
        ("point_ray-flat", nodes["point_ray"], 0, cluster([1, 2, 3], 5, 0, 32))]:
    write("cone_cull", name, node + [eps] + group)

tri = [0, 0, 0, 1, 0, 0, 0, 1, 0]
write("ray_triangle", "interior", [0.25, 0.25, 1, 0, 0, -1] + tri)
write("ray_triangle", "edge", [0.5, 0, 1, 0, 0, -1] + tri)
write("ray_triangle", "vertex", [0, 0, 1, 0, 0, -1] + tri)
write("ray_triangle", "grazing", [-1, 0.25, 0, 1, 0, 0] + tri)
write("ray_triangle", "degenerate", [0.25, 0, 1, 0, 0, -1] + [0, 0, 0, 1, 0, 0, 2, 0, 0])
write("ray_triangle", "huge", [HUGE / 4, HUGE / 4, HUGE, 0, 0, -1] + [x * HUGE for x in tri])
write("ray_triangle", "tiny", [TINY / 4, TINY / 4, TINY, 0, 0, -1] + [x * TINY for x in tri])
write("ray_triangle", "sliver", [0.5, 1e-4, 1, 0, 0, -1] + [0, 0, 0, 1, 0, 0, 1, 3e-4, 0])

scene = b'{"name": "s", "camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "fov": 45}, "size": [8, 8], ' \
        b'"materials": {"m": {"diffuse": [1, 1, 1]}}, "objects": [{"type": "box", "material": "m"}], ' \
        b'"lights": [{"position": [0, 3, 3], "color": [1, 1, 1]}]}'
write("scene_load", "json-box", raw=b"\x00" + scene)
write("scene_load", "json-truncated", raw=b"\x00" + scene[:40])
write("scene_load", "obj-triangle", raw=b"\x01v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
write("scene_load", "obj-bad-index", raw=b"\x01v 0 0 0\nf 1 2 9\n")
write("scene_load", "ply-triangle", raw=b"\x02ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      b"property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
write("scene_load", "ply-nan", raw=b"\x02ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
      b"property float y\nproperty float z\nend_header\nnan 0 0\n")
good_scene = b'{"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "fov_y_deg": 45}, "image": {"width": 8, ' \
             b'"height": 8}, "lights": [{"position": [0, 3, 3]}], "objects": [{"generator": "box"}]}'
write("scene_load", "json-valid", raw=b"\x00" + good_scene)
write("scene_load", "obj-cr-only", raw=b"\x01v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r")
write("scene_load", "obj-mixed-nan", raw=b"\x01v 0 0 0\r\nv 1 0 0\rv nan 0 0\nf 1 2 3\r")
write("scene_load", "mtl-material", raw=b"\x03newmtl a\nKa 0 0 0\nKd 0.8 0.7 0.6\nKs 0.5 0.5 0.5\nNs 96.07\n"
      b"Ni 1.5\nd 1\nillum 2\nKe 0 0 0\nTf 1 1 1\n")
write("scene_load", "mtl-nan", raw=b"\x03newmtl a\rKd nan 0.5 0.5\rNs 1e9\r")
# gzip's header holds a time stamp: mtime=0 keeps the seeds the same on every run.
obj_tri = b"o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
write("scene_load", "objgz-triangle", raw=b"\x04" + gzip.compress(obj_tri, mtime=0))
write("scene_load", "objgz-two-members", raw=b"\x04" + gzip.compress(obj_tri[:20], mtime=0)
      + gzip.compress(obj_tri[20:], mtime=0))
write("scene_load", "plygz-triangle", raw=b"\x05" + gzip.compress(
    b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    b"element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", mtime=0))

# spirv_load: small kernels compiled by glslc (when it is on the PATH; the outputs are committed): a
# store per invocation, a shared-memory scan with barriers and subgroup operations, a loop with a
# branch, and a module cut short.
SPIRV_SEEDS = {
    "store": "layout(local_size_x = 8) in;\nlayout(std430, binding = 0) buffer B { uint d[]; };\n"
             "void main() { d[gl_GlobalInvocationID.x] = gl_LocalInvocationIndex * 3u; }\n",
    "scan": "#extension GL_KHR_shader_subgroup_arithmetic : require\nlayout(local_size_x = 16) in;\n"
            "layout(std430, binding = 0) buffer B { uint d[]; };\nshared uint s[16];\n"
            "void main() { uint i = gl_LocalInvocationIndex; s[i] = subgroupInclusiveAdd(i); barrier();\n"
            "  d[gl_WorkGroupID.x * 16u + i] = s[15u - i]; }\n",
    "loop": "layout(local_size_x = 4) in;\nlayout(std430, binding = 0) buffer B { uint d[]; };\n"
            "void main() { uint n = 0u; for (uint k = 0u; k < gl_LocalInvocationIndex; ++k) { if (k % 2u == 0u) n += k; }\n"
            "  d[gl_GlobalInvocationID.x] = n; }\n",
}
if shutil.which("glslc"):
    with tempfile.TemporaryDirectory() as tmp:
        for name, body in SPIRV_SEEDS.items():
            src, out = os.path.join(tmp, name + ".comp"), os.path.join(tmp, name + ".spv")
            with open(src, "w") as f:
                f.write("#version 460\n" + body)
            subprocess.run(["glslc", "-O0", "-g", "--target-env=vulkan1.2", src, "-o", out], check=True)
            with open(out, "rb") as f:
                spv = f.read()
            write("spirv_load", name, raw=spv)
            if name == "scan":
                write("spirv_load", "truncated", raw=spv[: len(spv) // 2])
