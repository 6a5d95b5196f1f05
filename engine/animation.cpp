#include "animation.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <string>

namespace engine {
namespace {

Bounds instanceBounds(const Scene& scene, const Instance& inst) {
  Bounds b;
  const Mesh& mesh = scene.meshes[inst.mesh];
  for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p) {
    const Primitive& prim = scene.primitives[p];
    for (uint32_t v = 0; v < prim.vertexCount; ++v)
      b.grow(glm::vec3(inst.worldFromObject * glm::vec4(scene.positions[prim.vertexOffset + v], 1.0f)));
  }
  return b;
}

bool isEmissive(const Scene& scene, const Instance& inst) {
  const Mesh& mesh = scene.meshes[inst.mesh];
  for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p)
    if (scene.materials[scene.primitives[p].material].isEmissive()) return true;
  return false;
}

bool namedLikeAnObject(const std::string& name) {
  return name.find("block") != std::string::npos || name.find("box") != std::string::npos ||
         name.find("Block") != std::string::npos || name.find("Box") != std::string::npos;
}

}  // namespace

SceneAnimation makeSceneAnimation(const Scene& scene) {
  SceneAnimation a;
  if (scene.gltf.playable()) {
    a.gltf = true;
    return a;
  }
  const float extent = scene.worldBounds().extent();
  a.radius = 0.15f * extent;
  if (!scene.lights.empty()) {
    a.punctualLight = 0;
    a.lightBase = scene.lights[0].position;
    a.lightDirectionBase = scene.lights[0].direction;
  }
  float brightest = -1.0f, smallest = 1e30f;
  int named = -1;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    Bounds b = instanceBounds(scene, inst);
    if (b.empty()) continue;
    if (isEmissive(scene, inst)) {
      // Power ∝ area: the bounds' largest face stands in for it.
      glm::vec3 d = b.max - b.min;
      float area = glm::max(d.x * d.y, glm::max(d.y * d.z, d.x * d.z));
      if (a.punctualLight < 0 && area > brightest) {
        brightest = area;
        a.lightInstance = int(i);
      }
      continue;
    }
    if (named < 0 && namedLikeAnObject(inst.name)) named = int(i);
    if (b.extent() < smallest && b.extent() < 0.5f * extent) {
      smallest = b.extent();
      a.objectInstance = int(i);
    }
  }
  if (named >= 0) a.objectInstance = named;
  if (a.lightInstance >= 0) a.lightInstanceBase = scene.instances[size_t(a.lightInstance)].worldFromObject;
  if (a.objectInstance >= 0) {
    const Instance& inst = scene.instances[size_t(a.objectInstance)];
    a.objectBase = inst.worldFromObject;
    a.objectCenter = instanceBounds(scene, inst).center();
  }
  return a;
}

void animateScene(const SceneAnimation& a, float seconds, Scene& scene) {
  if (a.gltf) {
    poseGltfAnimations(scene, seconds);
    return;
  }
  const float phase = 6.2831853f * std::fmod(seconds / a.periodSeconds, 1.0f);
  // The light circles in the horizontal plane around where it started.
  glm::vec3 offset(a.radius * std::cos(phase) - a.radius, 0.0f, a.radius * std::sin(phase));
  if (a.punctualLight >= 0) {
    PunctualLight& light = scene.lights[size_t(a.punctualLight)];
    light.position = a.lightBase + offset;
    light.direction = glm::mat3(glm::rotate(glm::mat4(1.0f), phase, glm::vec3(0, 1, 0))) * a.lightDirectionBase;
  }
  if (a.lightInstance >= 0)
    scene.instances[size_t(a.lightInstance)].worldFromObject =
        glm::translate(glm::mat4(1.0f), offset) * a.lightInstanceBase;
  // The object turns about its vertical axis, swinging ±45° back and forth.
  if (a.objectInstance >= 0) {
    float angle = 0.785f * std::sin(phase);
    glm::mat4 turn = glm::translate(glm::mat4(1.0f), a.objectCenter) *
                     glm::rotate(glm::mat4(1.0f), angle, glm::vec3(0, 1, 0)) *
                     glm::translate(glm::mat4(1.0f), -a.objectCenter);
    scene.instances[size_t(a.objectInstance)].worldFromObject = turn * a.objectBase;
  }
}

void markAnimatedInstancesMovable(const SceneAnimation& animation, Scene& scene) {
  if (animation.gltf) markGltfAnimatedInstancesMovable(scene);
  for (int instance : {animation.lightInstance, animation.objectInstance})
    if (instance >= 0 && size_t(instance) < scene.instances.size()) scene.instances[size_t(instance)].movable = true;
}

bool poseScene(const Context& ctx, const SceneAnimation& animation, float seconds, Scene& scene, SceneGpu& gpu,
               std::string& error) {
  animateScene(animation, seconds, scene);
  bool recorded = false;
  const bool submitted = submitAndWait(
      ctx, [&](VkCommandBuffer cmd) { recorded = recordSceneTransformUpdate(ctx, cmd, scene, gpu, error); }, error);
  return recorded && submitted;
}

bool jumpScene(const Context& ctx, const SceneAnimation& animation, float seconds, Scene& scene, SceneGpu& gpu,
               std::string& error) {
  return poseScene(ctx, animation, seconds, scene, gpu, error) && poseScene(ctx, animation, seconds, scene, gpu, error);
}

}  // namespace engine
