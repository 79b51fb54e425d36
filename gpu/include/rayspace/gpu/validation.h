// The Khronos validation layer with synchronization validation, on request: `--validate` on any
// command, or RAYSPACE_VALIDATE=1 in the environment (ctest sets it for every test that touches
// Vulkan). Every message the layer reports makes the next checked Vulkan call fail with it
// (RS_VK in vulkan.cpp), so a spec violation is an error at the Vulkan boundary, not a log line.
#pragma once
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "rayspace/gpu/vulkan.h"
#include "rayspace/settings.h"

namespace rayspace::vk {

// Settings::validation, read when an instance is created. GPU-assisted validation instruments every
// kernel to check its descriptor accesses against their bounds (a frame takes several times longer).
// --validate asks for both; RAYSPACE_VALIDATE=1 (the test suite's environment) for synchronization
// validation alone, RAYSPACE_VALIDATE=gpu for both.
Validation RequestedValidation();
bool ValidationRequested();
bool GpuAssistedValidationRequested();

// The pNext chain and names an instance needs for validation; lives as long as the create info.
struct ValidationChain {
  VkValidationFeatureEnableEXT enables[2] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT,
                                             VK_VALIDATION_FEATURE_ENABLE_GPU_ASSISTED_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT, nullptr, 0, nullptr, 0, nullptr};
  VkDebugUtilsMessengerCreateInfoEXT messenger{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT, nullptr, 0, 0, 0, nullptr, nullptr};
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
};
// Adds the layer and synchronization validation (and GPU-assisted validation when requested) to `ici` (which must have no layers of its own) and
// the debug-utils extension to `extensions`, or fails naming the missing layer and its package.
Status AddValidation(VkInstanceCreateInfo& ici, ValidationChain& chain, std::vector<const char*>& extensions);
// The messenger that collects the layer's warnings and errors for the life of the instance.
Status CreateMessenger(VkInstance instance, VkDebugUtilsMessengerEXT& out);
void DestroyMessenger(VkInstance instance, VkDebugUtilsMessengerEXT messenger);

// Messages reported and not yet taken; TakeValidationMessages returns them as one line each
// ("N validation message(s): first; second; ...", at most three quoted) and clears them.
bool ValidationPending();
std::string TakeValidationMessages();
// Messages no call could fail with (the layer's report at instance teardown): printed on stderr and
// remembered, so that main() can exit non-zero.
void ReportAtExit(const std::string& messages);
bool ValidationFailedAtExit();

}  // namespace rayspace::vk
