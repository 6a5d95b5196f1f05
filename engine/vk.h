// The one include for Vulkan in this project: volk loads every entry point, so
// nothing links libvulkan directly.
//
// The engine's one error style, the module's too: a function that can fail
// takes `std::string& error`, writes one sentence there when it fails (what it
// was doing, the Vulkan call, its result) and returns false or an empty result.
// Called while `error` already holds a sentence, it does nothing and returns
// empty, so a run of creations is checked once at its end; destroy functions
// accept empty resources. No failure crosses the engine's API any other way:
// the glTF loader unwinds its parse with an exception of its own that
// loadGltf catches, and the one stop left is `dispatch` given push constants
// of the wrong size, a programming error (compute_program.h).
#pragma once
#include <volk.h>

#include <string>

namespace engine {

const char* vkResultName(VkResult result);

// True for VK_SUCCESS; otherwise writes "<what>: <call> failed with <result>" to `error` and returns false.
// `call` may be the whole call's text: only the function's name is kept.
bool vkSucceeded(VkResult result, const char* what, const char* call, std::string& error);

}  // namespace engine

// `VK_SUCCEEDED(error, "creating X", vkCreateX(...))`: the call's result through vkSucceeded.
#define VK_SUCCEEDED(error, what, call) engine::vkSucceeded((call), (what), #call, (error))
