// Scene motion for the demo and the dynamic-scene benchmarks: one light and
// one object move on closed paths, so a cache's temporal behaviour shows.
// The light is a punctual light if the scene has one (a point light circles,
// a spot or directional light also turns its direction about the vertical
// axis, once per loop), otherwise the emissive
// instance with the most power; the object is the instance named like a
// "block" or "box", otherwise the smallest non-emissive instance.
#pragma once
#include <string>

#include <glm/glm.hpp>

#include "scene.h"
#include "scene_gpu.h"

namespace engine {

struct SceneAnimation {
  int punctualLight = -1;                           // index into scene.lights, or -1
  int lightInstance = -1;                           // index into scene.instances (emissive), or -1
  int objectInstance = -1;                          // index into scene.instances, or -1
  glm::vec3 lightBase{0.0f};                        // punctual light position at t = 0
  glm::vec3 lightDirectionBase{0.0f, 0.0f, -1.0f};  // its direction at t = 0 (what moves a directional light)
  glm::mat4 lightInstanceBase{1.0f}, objectBase{1.0f};
  glm::vec3 objectCenter{0.0f};  // world-space centre of the object's bounds at t = 0
  float radius = 0.0f;           // metres: the light's circle, a fraction of the scene extent
  float periodSeconds = 8.0f;    // one loop of both paths
  bool gltf = false;             // the file's own animations play instead (engine/gltf_animation.h)
};

// Picks what moves: a file's glTF animations when it has any, otherwise one light and one object; an
// animation with nothing to move (no light, no object) is valid and does nothing.
SceneAnimation makeSceneAnimation(const Scene& scene);
// Declares the instances the animation moves `movable` (before createSceneGpu), as an engine declares its
// dynamic objects: their moves are then recorded updates that frames in flight never wait for (an
// instance that was not movable makes its first move rebuild the BVH's levels with the GPU idle).
void markAnimatedInstancesMovable(const SceneAnimation& animation, Scene& scene);
// Sets the moving light and object to their pose at `seconds` (periodic).
// Upload with recordSceneTransformUpdate.
void animateScene(const SceneAnimation& animation, float seconds, Scene& scene);
// animateScene, then uploads the pose and rebuilds the TLAS in a submission of its own; waits. False with
// the module's error when it refuses the pose.
bool poseScene(const Context& ctx, const SceneAnimation& animation, float seconds, Scene& scene, SceneGpu& gpu,
               std::string& error);
// poseScene for a jump: the pose is uploaded twice, so the instances' previous transforms (what
// the motion vectors come from) are this pose too; a jump has no motion, and without this every
// later frame would reproject the moved instances from where they were before it.
bool jumpScene(const Context& ctx, const SceneAnimation& animation, float seconds, Scene& scene, SceneGpu& gpu,
               std::string& error);

}  // namespace engine
