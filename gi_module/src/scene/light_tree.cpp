#include "scene/light_tree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace gi {
namespace {

// The angle between two unit directions (radians), 0 for the same one: acos of their dot is not (a unit
// vector's dot with itself can be 1 − 2⁻⁵³, whose acos is 1.5e-8).
double angleBetween(glm::dvec3 a, glm::dvec3 b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); }

// Fills nodes[at] with the node over order[first, last) and appends its children. Returns its cone.
DirectionCone buildNode(std::span<const EmitterBounds> emitters, std::vector<uint32_t>& order, size_t first,
                        size_t last, size_t at, uint32_t parent, std::vector<gpu::GpuLightNode>& nodes) {
  glm::vec3 low(std::numeric_limits<float>::max()), high(-std::numeric_limits<float>::max());
  glm::vec3 centresLow = low, centresHigh = high;
  double sum = 0.0;
  float cosFalloff = 1.0f;
  for (size_t i = first; i < last; ++i) {
    const EmitterBounds& e = emitters[order[i]];
    low = glm::min(low, e.low);
    high = glm::max(high, e.high);
    centresLow = glm::min(centresLow, 0.5f * (e.low + e.high));
    centresHigh = glm::max(centresHigh, 0.5f * (e.low + e.high));
    sum += e.power;
    cosFalloff = std::min(cosFalloff, e.cosFalloff);
  }
  gpu::GpuLightNode node{};
  node.centre = 0.5f * (low + high);
  // The half diagonal, rounded up so that every point is inside in float arithmetic; a point is a point.
  node.radius = low == high ? 0.0f : std::nextafter(0.5f * glm::length(high - low), std::numeric_limits<float>::max());
  node.power = float(sum);
  node.cosFalloff = cosFalloff;
  node.parent = parent;
  DirectionCone cone;
  if (last - first == 1) {
    node.child = gpu::LIGHT_NODE_LEAF | order[first];
    cone = emitters[order[first]].aim;
  } else {
    const glm::vec3 extent = centresHigh - centresLow;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const size_t middle = first + (last - first) / 2;
    std::nth_element(order.begin() + ptrdiff_t(first), order.begin() + ptrdiff_t(middle),
                     order.begin() + ptrdiff_t(last), [&](uint32_t a, uint32_t b) {
                       return emitters[a].low[axis] + emitters[a].high[axis] <
                              emitters[b].low[axis] + emitters[b].high[axis];
                     });
    node.child = uint32_t(nodes.size());
    nodes.resize(nodes.size() + 2);
    cone = coneUnion(buildNode(emitters, order, first, middle, node.child, uint32_t(at), nodes),
                     buildNode(emitters, order, middle, last, node.child + 1, uint32_t(at), nodes));
  }
  node.axis = glm::vec3(cone.axis);
  node.cosAim = float(std::cos(cone.angle));
  nodes[at] = node;
  return cone;
}

}  // namespace

DirectionCone coneUnion(const DirectionCone& a, const DirectionCone& b) {
  const double between = angleBetween(a.axis, b.axis);
  if (std::min(between + b.angle, std::numbers::pi) <= a.angle) return a;
  if (std::min(between + a.angle, std::numbers::pi) <= b.angle) return b;
  const double angle = 0.5 * (a.angle + between + b.angle);
  const glm::dvec3 normal = glm::cross(a.axis, b.axis);
  if (angle >= std::numbers::pi) return {a.axis, std::numbers::pi};
  if (glm::dot(normal, normal) < 1e-24)  // (anti)parallel axes: no plane to turn in; a's axis, widened to hold b
    return {a.axis, between < 0.5 * std::numbers::pi
                        ? std::min(std::max(a.angle, b.angle) + between + 1e-6, std::numbers::pi)
                        : std::numbers::pi};
  // Turn a's axis towards b's by the part of the new half-angle a does not cover.
  const double turn = angle - a.angle;
  const glm::dvec3 axis = a.axis * std::cos(turn) + glm::cross(glm::normalize(normal), a.axis) * std::sin(turn);
  return {glm::normalize(axis), std::min(angle + 1e-6, std::numbers::pi)};  // 1e-6: the rounding of the turn
}

std::vector<gpu::GpuLightNode> buildLightTree(std::span<const EmitterBounds> emitters, std::vector<uint32_t> order) {
  std::vector<gpu::GpuLightNode> nodes;
  if (order.empty()) return nodes;
  nodes.resize(1);
  buildNode(emitters, order, 0, order.size(), 0, 0u, nodes);
  return nodes;
}

std::vector<uint32_t> treeCut(const std::vector<gpu::GpuLightNode>& nodes, uint32_t size) {
  std::vector<uint32_t> cut{0u};
  while (cut.size() < size) {
    size_t widest = cut.size();
    for (size_t i = 0; i < cut.size(); ++i)
      if (!(nodes[cut[i]].child & gpu::LIGHT_NODE_LEAF) &&
          (widest == cut.size() || nodes[cut[i]].power > nodes[cut[widest]].power))
        widest = i;
    if (widest == cut.size()) break;  // every subtree a leaf
    const uint32_t child = nodes[cut[widest]].child;
    cut[widest] = child;
    cut.insert(cut.begin() + ptrdiff_t(widest) + 1, child + 1);
  }
  return cut;
}

}  // namespace gi
