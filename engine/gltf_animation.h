// glTF animation as the engine plays it: the node hierarchy the loader
// flattened into instances and lights, kept with each node's rest pose; the
// animations' translation, rotation and scale channels (LINEAR, STEP,
// CUBICSPLINE); skins (joints, inverse bind matrices; JOINTS_0/WEIGHTS_0 per
// vertex). posing a scene at t seconds moves its instances and lights (rigid,
// through gi::updateInstances and gi::updateLights) and gives each skin's
// joint matrices, which skinning.comp applies (engine/skinning.h). Every
// animation of the file plays at once, each looping over its own duration.
// What is not played (morph targets, animated cameras) is named in a warning
// by the loader.
#pragma once
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <string>
#include <vector>

namespace engine {

struct Scene;

struct SceneNode {
  int parent = -1;
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
  glm::vec3 scale{1.0f};
  bool hasMatrix = false;  // a node given by `matrix` (never animated: glTF forbids both)
  glm::mat4 matrix{1.0f};
  std::vector<int> instances;  // scene.instances this node placed (not skinned ones: those stay at identity)
  std::vector<int> lights;     // scene.lights it placed
};

struct AnimationSampler {
  enum class Interpolation { Linear, Step, CubicSpline };
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> times;       // seconds, increasing
  std::vector<glm::vec4> values;  // xyz (translation, scale) or xyzw (rotation); CUBICSPLINE: in-tangent, value,
                                  // out-tangent per key
};

struct AnimationChannel {
  enum class Path { Translation, Rotation, Scale };
  int node = 0;
  Path path = Path::Translation;
  int sampler = 0;
};

struct Animation {
  std::string name;
  std::vector<AnimationSampler> samplers;
  std::vector<AnimationChannel> channels;
  float seconds = 0.0f;  // the last key's time: the loop's length
};

struct Skin {
  std::vector<int> joints;             // nodes
  std::vector<glm::mat4> inverseBind;  // per joint
};

// A mesh the loader made for one skinned node: its vertices are posed by `skin`.
struct SkinnedMesh {
  uint32_t mesh = 0;
  uint32_t skin = 0;
};

struct SceneAnimations {
  std::vector<SceneNode> nodes;  // the file's nodes, in its order
  std::vector<Animation> animations;
  std::vector<Skin> skins;
  std::vector<SkinnedMesh> skinnedMeshes;
  std::vector<glm::uvec4> vertexJoints;  // per scene vertex (zero for vertices no skin poses)
  std::vector<glm::vec4> vertexWeights;
  std::vector<glm::vec3> bindPositions, bindNormals;  // per scene vertex: the file's, before any pose
  std::vector<glm::mat4> jointMatrices;               // the current pose's, every skin's in turn (poseGltfAnimations)
  bool playable() const { return !animations.empty(); }
};

// A node's local transform: its matrix, or translation × rotation × scale.
glm::mat4 localMatrix(const SceneNode& node);
// Every node's world transform with the animations applied at `seconds`.
std::vector<glm::mat4> worldTransformsAt(const SceneAnimations& a, float seconds);
// Poses the scene at `seconds`: instances and lights placed by animated nodes move and every skin's joint
// matrices (world × inverse bind) go to scene.gltf.jointMatrices, skin by skin (firstJoint gives where each
// starts). recordSceneTransformUpdate uploads the pose and skins the skinned meshes on the device.
void poseGltfAnimations(Scene& scene, float seconds);
// Declares the instances placed by animated nodes (or their descendants) movable, before createSceneGpu.
void markGltfAnimatedInstancesMovable(Scene& scene);
uint32_t firstJoint(const SceneAnimations& a, uint32_t skin);
// Linear-blend skinning on the CPU: the skinned meshes' vertices of scene.positions and scene.normals posed by
// scene.gltf.jointMatrices, from the bind pose. The loader poses t = 0 this way, so a still render and the
// CPU tracer see the first frame; frames in motion are skinned on the device (engine/skinning.h).
void skinOnCpu(Scene& scene);

}  // namespace engine
