// A pass's kernel contract checked on SPIR-V by reflection (SPIRV-Cross): what a user's kernel
// (`--kernel PASS=FILE`) must declare to run in place of the built-in one. The registry
// (rayspace/pass_registry.h) gives the pass's bindings; the built-in kernel's push-constant block,
// compiled from rayspace/contract.h, gives the layout the host pushes.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rayspace/gpu/vulkan.h"
#include "rayspace/install_paths.h"
#include "rayspace/pass_registry.h"

namespace rayspace::gpu_backend {

// What reflection finds in a compute kernel.
struct KernelInterface {
  struct Binding {
    std::uint32_t set = 0, binding = 0;
    std::string name;  // the block's type name, e.g. "Flags"
    bool storage_buffer = true;
  };
  std::vector<Binding> bindings;
  // The push-constant block flattened to its scalar members: byte offset and GLSL type ("uint", ...).
  struct Scalar {
    std::uint32_t offset = 0;
    std::string type;
  };
  std::vector<Scalar> push;
  std::uint32_t push_bytes = 0;
  bool compute = false;
  // The workgroup's x size comes from specialization constant 1 (the host's --local-size), y = z = 1.
  bool local_size_from_constant_1 = false;
};

vk::Status ReflectKernel(std::span<const std::uint32_t> spirv, KernelInterface& out);

// Ok when `spirv` can replace the built-in kernel of `pass`; otherwise the message names the pass and
// the first mismatch (a binding, a descriptor type, a push-constant member, the workgroup size).
vk::Status CheckKernel(const PassSpec& pass, std::span<const std::uint32_t> spirv);

// Reads a user's kernel: a .spv file as it is, or a .comp file compiled with glslc as the built-in
// kernels are (-O0 -g, Vulkan 1.2; include paths: the file's folder, then the kernels' GLSL and the
// contract headers of `data`: an install's or the source tree's, rayspace/install_paths.h).
vk::Status LoadKernelFile(const std::string& path, std::vector<std::uint32_t>& out, const DataPaths& data = FindDataPaths());

}  // namespace rayspace::gpu_backend
