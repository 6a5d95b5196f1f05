#include "gltf_animation.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

#include "scene.h"

namespace engine {
namespace {

// The sampler's value at t (clamped to its keys), glTF 2.0 §3.11 "Interpolation".
glm::vec4 sample(const AnimationSampler& s, float t, bool rotation) {
  const size_t keys = s.times.size();
  const bool cubic = s.interpolation == AnimationSampler::Interpolation::CubicSpline;
  auto value = [&](size_t k) { return cubic ? s.values[3 * k + 1] : s.values[k]; };
  if (keys == 0) return glm::vec4(0.0f);
  if (t <= s.times.front()) return value(0);
  if (t >= s.times.back()) return value(keys - 1);
  const size_t k = size_t(std::upper_bound(s.times.begin(), s.times.end(), t) - s.times.begin()) - 1;
  const float t0 = s.times[k], t1 = s.times[k + 1], dt = t1 - t0, u = dt > 0.0f ? (t - t0) / dt : 0.0f;
  glm::vec4 out;
  switch (s.interpolation) {
    case AnimationSampler::Interpolation::Step: return value(k);
    case AnimationSampler::Interpolation::Linear:
      if (rotation) {
        const glm::quat a(s.values[k].w, s.values[k].x, s.values[k].y, s.values[k].z);
        const glm::quat b(s.values[k + 1].w, s.values[k + 1].x, s.values[k + 1].y, s.values[k + 1].z);
        const glm::quat q = glm::slerp(a, b, u);
        return glm::vec4(q.x, q.y, q.z, q.w);
      }
      return glm::mix(s.values[k], s.values[k + 1], u);
    case AnimationSampler::Interpolation::CubicSpline: {
      // Hermite: p0 = value k, m0 = dt × out-tangent k, p1 = value k+1, m1 = dt × in-tangent k+1.
      const glm::vec4 p0 = s.values[3 * k + 1], m0 = dt * s.values[3 * k + 2];
      const glm::vec4 p1 = s.values[3 * (k + 1) + 1], m1 = dt * s.values[3 * (k + 1)];
      const float u2 = u * u, u3 = u2 * u;
      out = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * m1;
      return rotation ? glm::normalize(out) : out;
    }
  }
  return value(k);
}

}  // namespace

glm::mat4 localMatrix(const SceneNode& node) {
  if (node.hasMatrix) return node.matrix;
  return glm::translate(glm::mat4(1.0f), node.translation) * glm::mat4_cast(node.rotation) *
         glm::scale(glm::mat4(1.0f), node.scale);
}

std::vector<glm::mat4> worldTransformsAt(const SceneAnimations& a, float seconds) {
  std::vector<SceneNode> posed = a.nodes;  // the rest poses, the channels' values applied
  for (const Animation& anim : a.animations) {
    const float t = anim.seconds > 0.0f ? std::fmod(seconds, anim.seconds) : 0.0f;
    for (const AnimationChannel& c : anim.channels) {
      const glm::vec4 v = sample(anim.samplers[c.sampler], t, c.path == AnimationChannel::Path::Rotation);
      SceneNode& node = posed[size_t(c.node)];
      if (c.path == AnimationChannel::Path::Translation)
        node.translation = glm::vec3(v);
      else if (c.path == AnimationChannel::Path::Scale)
        node.scale = glm::vec3(v);
      else
        node.rotation = glm::normalize(glm::quat(v.w, v.x, v.y, v.z));
    }
  }
  std::vector<glm::mat4> world(a.nodes.size());
  std::vector<char> done(a.nodes.size(), 0);
  // Parents first: the loader refused cycles, so following parents ends.
  auto resolve = [&](auto&& self, size_t n) -> const glm::mat4& {
    if (done[n]) return world[n];
    const SceneNode& node = posed[n];
    const glm::mat4 local = localMatrix(node);
    world[n] = node.parent >= 0 ? self(self, size_t(node.parent)) * local : local;
    done[n] = 1;
    return world[n];
  };
  for (size_t n = 0; n < a.nodes.size(); ++n) resolve(resolve, n);
  return world;
}

uint32_t firstJoint(const SceneAnimations& a, uint32_t skin) {
  uint32_t first = 0;
  for (uint32_t s = 0; s < skin; ++s) first += uint32_t(a.skins[s].joints.size());
  return first;
}

void poseGltfAnimations(Scene& scene, float seconds) {
  SceneAnimations& a = scene.gltf;
  const std::vector<glm::mat4> world = worldTransformsAt(a, seconds);
  for (size_t n = 0; n < a.nodes.size(); ++n) {
    for (int i : a.nodes[n].instances) scene.instances[size_t(i)].worldFromObject = world[n];
    for (int l : a.nodes[n].lights) {
      PunctualLight& light = scene.lights[size_t(l)];
      light.position = glm::vec3(world[n][3]);
      const glm::vec3 direction = -glm::vec3(world[n][2]);
      if (glm::length(direction) > 0.0f) light.direction = glm::normalize(direction);
    }
  }
  a.jointMatrices.clear();
  for (const Skin& skin : a.skins)
    for (size_t j = 0; j < skin.joints.size(); ++j)
      a.jointMatrices.push_back(world[size_t(skin.joints[j])] * skin.inverseBind[j]);
}

void markGltfAnimatedInstancesMovable(Scene& scene) {
  const SceneAnimations& a = scene.gltf;
  std::vector<char> animated(a.nodes.size(), 0);
  for (const Animation& anim : a.animations)
    for (const AnimationChannel& c : anim.channels) animated[size_t(c.node)] = 1;
  // A node moves when it or an ancestor is animated.
  auto moves = [&](auto&& self, size_t n) -> bool {
    return animated[n] || (a.nodes[n].parent >= 0 && self(self, size_t(a.nodes[n].parent)));
  };
  for (size_t n = 0; n < a.nodes.size(); ++n)
    if (moves(moves, n))
      for (int i : a.nodes[n].instances) scene.instances[size_t(i)].movable = true;
}

void skinOnCpu(Scene& scene) {
  const SceneAnimations& a = scene.gltf;
  const std::vector<glm::mat4>& joints = a.jointMatrices;
  for (const SkinnedMesh& sm : a.skinnedMeshes) {
    const uint32_t first = firstJoint(a, sm.skin);
    const Mesh& mesh = scene.meshes[sm.mesh];
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p)
      for (uint32_t v = scene.primitives[p].vertexOffset;
           v < scene.primitives[p].vertexOffset + scene.primitives[p].vertexCount; ++v) {
        glm::mat4 m(0.0f);
        for (int k = 0; k < 4; ++k) m += a.vertexWeights[v][k] * joints[first + a.vertexJoints[v][k]];
        scene.positions[v] = glm::vec3(m * glm::vec4(a.bindPositions[v], 1.0f));
        const glm::vec3 n = glm::transpose(glm::inverse(glm::mat3(m))) * a.bindNormals[v];
        scene.normals[v] = glm::length(n) > 0.0f ? glm::normalize(n) : a.bindNormals[v];
      }
  }
}

}  // namespace engine
