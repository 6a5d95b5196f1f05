// Many-light scenes from a scene's own lights: its point lights replaced by N
// of the same total intensity on a grid at their mean height (issue 31's
// measurements: the cost and error of next-event estimation against the
// light count, the light as a whole unchanged).
#pragma once
#include <cstdint>
#include <string>

#include "scene.h"

namespace engine {

// Replaces `scene`'s point lights by `count` point lights (≥ 1) whose
// intensities sum to theirs (W/sr, per channel), on a cols × rows grid over
// the scene's horizontal extent inset by a tenth on each side, at the point
// lights' mean height. Spot and directional lights stay. False with `error`
// when the scene has no point light or `count` is 0.
bool spreadPointLights(Scene& scene, uint32_t count, std::string& error);

}  // namespace engine
