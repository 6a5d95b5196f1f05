// The binary tree LIGHT_SAMPLER_TREE walks (shared/light_tree.h's GpuLightNode), over any emitters the
// scene bounds: the point and spot lights (scene_tables.cpp's lightTable) and the emissive triangles
// (emissiveTable). No Vulkan; units metres and the sampling power of the emitters' table.
#pragma once
#include <glm/glm.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "shared/light_tree.h"

namespace gi {

// A cone of directions (Conty Estevez & Kulla 2018): every direction within `angle` of `axis` (radians,
// [0, π]); a node's cosAim.
struct DirectionCone {
  glm::dvec3 axis{0.0, 0.0, 1.0};
  double angle = 0.0;
};

// The smallest cone round both (PBRT-v4's DirectionCone Union).
DirectionCone coneUnion(const DirectionCone& a, const DirectionCone& b);

// One emitter as the tree bounds it.
struct EmitterBounds {
  glm::vec3 low{0.0f}, high{0.0f};  // world, metres: a box round its points (a point light's position twice)
  DirectionCone aim;                // the directions it sends light in
  double power = 0.0;               // its sampling power (≥ 0; 0 is never picked)
  float cosFalloff = 1.0f;          // GpuLightNode::cosFalloff: 1 for point and spot lights, 0 for a cosine emitter
};

// The tree over emitters[order[i]] (every entry once): median splits of the longest axis of their boxes'
// centres, two children adjacent, node 0 the root; a leaf's child is LIGHT_NODE_LEAF | its emitter's index,
// each node's parent its parent's index (the root's 0). 2n − 1 nodes for n emitters; none for none.
std::vector<gpu::GpuLightNode> buildLightTree(std::span<const EmitterBounds> emitters, std::vector<uint32_t> order);

// The cut of at most `size` nodes whose subtrees hold every leaf of the tree once: from the root, the
// node with the most power is split into its children until there are `size` (or only leaves).
std::vector<uint32_t> treeCut(const std::vector<gpu::GpuLightNode>& nodes, uint32_t size);

}  // namespace gi
