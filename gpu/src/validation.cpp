#include "rayspace/gpu/validation.h"
#include "rayspace/settings.h"

#include <fmt/format.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

namespace rayspace::vk {
namespace {

std::mutex g_mutex;
std::vector<std::string> g_messages;
std::atomic<bool> g_pending{false};

// The layer calls this from whichever thread made the offending call.
VKAPI_ATTR VkBool32 VKAPI_CALL OnMessage(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_messages.emplace_back(data && data->pMessage ? data->pMessage : "(no text)");
  g_pending = true;
  return VK_FALSE;  // the call itself goes on, as it would without the layer
}

void FillMessenger(VkDebugUtilsMessengerCreateInfoEXT& m) {
  m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
  m.pfnUserCallback = OnMessage;
}

}  // namespace

Validation RequestedValidation() {
  const Validation v = CurrentSettings().validation;
  if (v != Validation::kFromEnvironment) return v;
  const char* e = std::getenv("RAYSPACE_VALIDATE");
  if (!e || !*e || std::strcmp(e, "0") == 0) return Validation::kOff;
  return std::strcmp(e, "gpu") == 0 ? Validation::kGpuAssisted : Validation::kSynchronization;
}

bool ValidationRequested() { return RequestedValidation() != Validation::kOff; }
bool GpuAssistedValidationRequested() { return RequestedValidation() == Validation::kGpuAssisted; }

Status AddValidation(VkInstanceCreateInfo& ici, ValidationChain& chain, std::vector<const char*>& extensions) {
  std::uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  bool found = false;
  for (const VkLayerProperties& l : layers) found |= std::strcmp(l.layerName, chain.layer) == 0;
  if (!found)
    return Status::Fail(fmt::format("--validate: the Vulkan layer {} is not installed (Debian package "
                                    "vulkan-validationlayers)",
                                    chain.layer));
  FillMessenger(chain.messenger);  // also reports what instance creation and destruction do
  chain.features.enabledValidationFeatureCount = GpuAssistedValidationRequested() ? 2 : 1;
  chain.features.pEnabledValidationFeatures = chain.enables;
  chain.features.pNext = &chain.messenger;
  chain.messenger.pNext = ici.pNext;
  ici.pNext = &chain.features;
  ici.enabledLayerCount = 1;
  ici.ppEnabledLayerNames = &chain.layer;
  extensions.push_back(chain.extension);
  return Status::Ok();
}

Status CreateMessenger(VkInstance instance, VkDebugUtilsMessengerEXT& out) {
  auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
  if (!create) return Status::Fail("--validate: vkCreateDebugUtilsMessengerEXT is not available");
  VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  FillMessenger(m);
  if (VkResult r = create(instance, &m, nullptr, &out); r != VK_SUCCESS) return Status::Fail("vkCreateDebugUtilsMessengerEXT", r);
  return Status::Ok();
}

void DestroyMessenger(VkInstance instance, VkDebugUtilsMessengerEXT messenger) {
  auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
  if (destroy && messenger) destroy(instance, messenger, nullptr);
}

bool ValidationPending() { return g_pending; }

namespace {
std::atomic<bool> g_failed_at_exit{false};
}  // namespace

void ReportAtExit(const std::string& messages) {
  std::fprintf(stderr, "rayspace: Vulkan validation at teardown: %s\n", messages.c_str());
  g_failed_at_exit = true;
}

bool ValidationFailedAtExit() { return g_failed_at_exit; }

std::string TakeValidationMessages() {
  std::lock_guard<std::mutex> lock(g_mutex);
  std::string s = fmt::format("{} validation message(s)", g_messages.size());
  for (std::size_t i = 0; i < g_messages.size() && i < 3; ++i) s += (i ? "; " : ": ") + g_messages[i];
  g_messages.clear();
  g_pending = false;
  return s;
}

}  // namespace rayspace::vk
