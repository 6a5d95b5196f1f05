#include "scene/light_tree.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gi {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The angle between two directions (radians), 0 for the same one: acos of their dot is not (a unit vector's
// dot with itself can be 1 − 2⁻⁵³, whose acos is 1.5e-8).
double angleBetween(glm::dvec3 a, glm::dvec3 b) { return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)); }

// The octahedral code (2 × 16-bit snorm) of a unit vector: lightNodeAxis's inverse, to the nearest code.
uint32_t octahedralCode(glm::dvec3 n) {
  n /= std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
  glm::dvec2 e(n.x, n.y);
  if (n.z < 0.0)
    e = (1.0 - glm::abs(glm::dvec2(n.y, n.x))) * glm::dvec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
  return gpu::packSnorm2x16(glm::vec2(e));
}

// The largest half float at most v (its bits): a cosine rounded down widens the angle it bounds.
uint32_t halfAtMost(float v) {
  uint32_t h = gpu::packHalf2x16(glm::vec2(v, 0.0f)) & 0xffffu;
  const float back = gpu::unpackHalf2x16(h).x;
  if (back > v) h = back == 0.0f ? 0x8001u : back > 0.0f ? h - 1u : h + 1u;  // one step towards −∞
  return h;
}

// The node's aim cone (axis, half-angle in radians) as GpuStoredLightNode holds it: the axis through its
// octahedral code (a code that codes itself again, so storing it loses nothing more), the half-angle widened
// by the angle between that axis and the cone's own, plus 1e-5 for the shaders' normalize, and cosAim and
// cosFalloff rounded down to half floats: the cone holds every direction the exact one held. Returns that
// cone, which the parent's then holds.
DirectionCone roundToStored(const DirectionCone& cone, gpu::GpuLightNode& node) {
  uint32_t code = octahedralCode(cone.axis);
  for (int i = 0; i < 4; ++i) {
    const uint32_t again = octahedralCode(glm::dvec3(gpu::lightNodeAxis(code)));
    if (again == code) break;
    code = again;
  }
  node.axis = gpu::lightNodeAxis(code);
  const double turn = angleBetween(glm::dvec3(node.axis), cone.axis);
  const double angle = cone.angle >= kPi ? kPi : std::min(cone.angle + turn + 1e-5, kPi);
  node.cosAim = gpu::unpackHalf2x16(halfAtMost(float(std::cos(angle)))).x;
  node.cosFalloff = gpu::unpackHalf2x16(halfAtMost(node.cosFalloff)).x;
  return {glm::normalize(glm::dvec3(node.axis)), std::acos(std::clamp(double(node.cosAim), -1.0, 1.0))};
}

// Fills nodes[at] with the node over order[first, last) and appends its children. Returns its cone as
// stored (roundToStored).
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
    const DirectionCone a = buildNode(emitters, order, first, middle, node.child, uint32_t(at), nodes);
    const DirectionCone b = buildNode(emitters, order, middle, last, node.child + 1, uint32_t(at), nodes);
    cone = coneUnion(a, b);
    // A child's stored cone that holds the other's is the node's as it is: rounded again it would widen by
    // a half float's step a level (a hall of panels that all face down).
    for (const auto& [childCone, child] : {std::pair(a, node.child), std::pair(b, node.child + 1)})
      if (cone.axis == childCone.axis && cone.angle == childCone.angle) {
        node.axis = nodes[child].axis;
        node.cosAim = nodes[child].cosAim;
        node.cosFalloff = gpu::unpackHalf2x16(halfAtMost(node.cosFalloff)).x;
        nodes[at] = node;
        return cone;
      }
  }
  const DirectionCone stored = roundToStored(cone, node);
  nodes[at] = node;
  return stored;
}

}  // namespace

DirectionCone coneUnion(const DirectionCone& a, const DirectionCone& b) {
  const double between = angleBetween(a.axis, b.axis);
  if (std::min(between + b.angle, kPi) <= a.angle) return a;
  if (std::min(between + a.angle, kPi) <= b.angle) return b;
  const double angle = 0.5 * (a.angle + between + b.angle);
  const glm::dvec3 normal = glm::cross(a.axis, b.axis);
  if (angle >= kPi) return {a.axis, kPi};
  if (glm::dot(normal, normal) < 1e-24)  // (anti)parallel axes: no plane to turn in; a's axis, widened to hold b
    return {a.axis, between < 0.5 * kPi ? std::min(std::max(a.angle, b.angle) + between + 1e-6, kPi) : kPi};
  // Turn a's axis towards b's by the part of the new half-angle a does not cover.
  const double turn = angle - a.angle;
  const glm::dvec3 axis = a.axis * std::cos(turn) + glm::cross(glm::normalize(normal), a.axis) * std::sin(turn);
  return {glm::normalize(axis), std::min(angle + 1e-6, kPi)};  // 1e-6: the rounding of the turn
}

std::vector<gpu::GpuLightNode> buildLightTree(std::span<const EmitterBounds> emitters, std::vector<uint32_t> order) {
  std::vector<gpu::GpuLightNode> nodes;
  if (order.empty()) return nodes;
  nodes.resize(1);
  buildNode(emitters, order, 0, order.size(), 0, 0u, nodes);
  return nodes;
}

gpu::GpuStoredLightNode storedLightNode(const gpu::GpuLightNode& n) {
  const uint32_t cosines = halfAtMost(n.cosAim) | halfAtMost(n.cosFalloff) << 16;
  return {n.centre, n.radius, octahedralCode(glm::dvec3(n.axis)), cosines, n.power, n.child};
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
