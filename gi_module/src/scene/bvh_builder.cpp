#include "bvh_builder.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>

namespace gi {
namespace {

// Leaves of up to 4 triangles: on lavapipe a box test and a triangle test cost
// about the same; 2, 4 and 8 measured within noise (docs/RESULTS.md).
constexpr uint32_t kLeafSize = 4;
constexpr size_t kSplitCapacity = 2;  // spatial splits may make up to this many fragments per triangle in all
constexpr uint32_t kMaxDepth = 40;    // per level; with a top level under 20 deep the stack holds both
static_assert(kLeafSize <= gpu::BVH_MAX_LEAF_SIZE);
static_assert(kMaxDepth + 20 < gpu::BVH_STACK_SIZE);

// Embree's build tree, allocated in its thread-local arenas and flattened
// into GpuBvhNode once the build returns.
constexpr uint32_t kWidth = gpu::BVH_WIDTH;

struct TreeNode {
  bool leaf = false;
  uint32_t count = 0;  // leaf: primitives; inner: children
  RTCBounds bounds[kWidth]{};
  TreeNode* children[kWidth]{};
  uint32_t primitives[kLeafSize]{};
};

TreeNode* allocateNode(RTCThreadLocalAllocator alloc) {
  void* memory = rtcThreadLocalAlloc(alloc, sizeof(TreeNode), 16);
  return memory ? new (memory) TreeNode{} : nullptr;
}

void* createInner(RTCThreadLocalAllocator alloc, unsigned int, void*) { return allocateNode(alloc); }

void setChildren(void* node, void** children, unsigned int count, void*) {
  TreeNode* n = static_cast<TreeNode*>(node);
  n->count = std::min<uint32_t>(count, kWidth);
  for (uint32_t i = 0; i < n->count; ++i) n->children[i] = static_cast<TreeNode*>(children[i]);
}

void setBounds(void* node, const RTCBounds** bounds, unsigned int count, void*) {
  for (uint32_t i = 0; i < count && i < kWidth; ++i) static_cast<TreeNode*>(node)->bounds[i] = *bounds[i];
}

void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* primitives, size_t count, void*) {
  TreeNode* node = allocateNode(alloc);
  if (!node) return nullptr;
  node->leaf = true;
  node->count = uint32_t(std::min<size_t>(count, kLeafSize));
  for (uint32_t i = 0; i < node->count; ++i) node->primitives[i] = primitives[i].primID;
  return node;
}

const gpu::GpuBvhNode kEmptyNode{glm::vec4(INFINITY),          glm::vec4(INFINITY),  glm::vec4(INFINITY),
                                 glm::vec4(-INFINITY),         glm::vec4(-INFINITY), glm::vec4(-INFINITY),
                                 glm::uvec4(gpu::BVH_NO_CHILD)};

void setChild(gpu::GpuBvhNode& node, uint32_t slot, glm::vec3 lo, glm::vec3 hi, uint32_t ref) {
  node.minX[slot] = lo.x;
  node.minY[slot] = lo.y;
  node.minZ[slot] = lo.z;
  node.maxX[slot] = hi.x;
  node.maxY[slot] = hi.y;
  node.maxZ[slot] = hi.z;
  node.child[slot] = ref;
}

struct Flattener {
  std::vector<gpu::GpuBvhNode>& nodes;
  std::vector<uint32_t>& order;  // item ids in leaf order
  uint32_t itemBase;             // the index `order[0]` will have in the final item array

  uint32_t emit(const TreeNode* n) {
    if (n->leaf) {
      uint32_t first = itemBase + uint32_t(order.size());
      if (first > gpu::BVH_LEAF_FIRST_MASK)
        throw std::runtime_error("BVH: more primitives than a leaf reference can address");
      for (uint32_t i = 0; i < n->count; ++i) order.push_back(n->primitives[i]);
      return gpu::BVH_LEAF_BIT | ((n->count - 1u) << gpu::BVH_LEAF_COUNT_SHIFT) | first;
    }
    uint32_t index = uint32_t(nodes.size());
    nodes.push_back(kEmptyNode);
    for (uint32_t i = 0; i < n->count; ++i) {
      uint32_t ref = emit(n->children[i]);
      const RTCBounds& b = n->bounds[i];
      setChild(nodes[index], i, {b.lower_x, b.lower_y, b.lower_z}, {b.upper_x, b.upper_y, b.upper_z}, ref);
    }
    return index;
  }
};

struct EmbreeDevice {
  RTCDevice device = rtcNewDevice(nullptr);
  ~EmbreeDevice() {
    if (device) rtcReleaseDevice(device);
  }
};

// Spatial splits (Embree's high-quality build): clips triangle `primID`
// (already clipped to the primitive's box) at `position` along `dimension`.
void splitTriangle(const RTCBuildPrimitive* prim, unsigned int dimension, float position, RTCBounds* left,
                   RTCBounds* right, void* userPtr) {
  const auto& triangles = *static_cast<const std::vector<gpu::GpuBvhTriangle>*>(userPtr);
  const gpu::GpuBvhTriangle& t = triangles[prim->primID];
  const glm::vec3 v[3] = {t.v0, t.v0 + t.edge1, t.v0 + t.edge2};
  glm::vec3 lLo(INFINITY), lHi(-INFINITY), rLo(INFINITY), rHi(-INFINITY);
  for (int i = 0; i < 3; ++i) {
    const glm::vec3& a = v[i];
    const glm::vec3& b = v[(i + 1) % 3];
    if (a[dimension] <= position) lLo = glm::min(lLo, a), lHi = glm::max(lHi, a);
    if (a[dimension] >= position) rLo = glm::min(rLo, a), rHi = glm::max(rHi, a);
    if ((a[dimension] < position && b[dimension] > position) || (a[dimension] > position && b[dimension] < position)) {
      glm::vec3 c = glm::mix(a, b, (position - a[dimension]) / (b[dimension] - a[dimension]));
      c[dimension] = position;
      lLo = glm::min(lLo, c), lHi = glm::max(lHi, c);
      rLo = glm::min(rLo, c), rHi = glm::max(rHi, c);
    }
  }
  // Never grow beyond the fragment being split.
  glm::vec3 pLo(prim->lower_x, prim->lower_y, prim->lower_z), pHi(prim->upper_x, prim->upper_y, prim->upper_z);
  glm::vec3 leftHi = pHi, rightLo = pLo;
  leftHi[dimension] = position;
  rightLo[dimension] = position;
  lLo = glm::max(lLo, pLo), lHi = glm::min(lHi, leftHi);
  rLo = glm::max(rLo, rightLo), rHi = glm::min(rHi, pHi);
  // Float rounding can leave a side empty; its half of the fragment's box is
  // then a safe (larger) bound, and Embree needs a non-empty one.
  if (glm::any(glm::greaterThan(lLo, lHi))) lLo = pLo, lHi = leftHi;
  if (glm::any(glm::greaterThan(rLo, rHi))) rLo = rightLo, rHi = pHi;
  *left = RTCBounds{lLo.x, lLo.y, lLo.z, 0.0f, lHi.x, lHi.y, lHi.z, 0.0f};
  *right = RTCBounds{rLo.x, rLo.y, rLo.z, 0.0f, rHi.x, rHi.y, rHi.z, 0.0f};
}

// Builds one tree over `boxes` (primID = the item's id) and appends its nodes
// (root first) to `nodes` and its items' ids, in leaf order, to `order`.
// Returns the root node's index and the union of the boxes. With `triangles`,
// the build may split them spatially (a triangle then appears in more than
// one leaf), which separates Sponza's long overlapping triangles.
uint32_t buildTree(RTCDevice device, std::vector<RTCBuildPrimitive> boxes, uint32_t leafSize, uint32_t itemBase,
                   std::vector<gpu::GpuBvhNode>& nodes, std::vector<uint32_t>& order, glm::vec3& lo, glm::vec3& hi,
                   const std::vector<gpu::GpuBvhTriangle>* triangles = nullptr) {
  lo = glm::vec3(INFINITY);
  hi = glm::vec3(-INFINITY);
  for (const RTCBuildPrimitive& b : boxes) {
    lo = glm::min(lo, glm::vec3(b.lower_x, b.lower_y, b.lower_z));
    hi = glm::max(hi, glm::vec3(b.upper_x, b.upper_y, b.upper_z));
  }
  uint32_t root = uint32_t(nodes.size());
  nodes.push_back(kEmptyNode);
  if (boxes.empty()) return root;
  RTCBVH bvh = rtcNewBVH(device);
  RTCBuildArguments args = rtcDefaultBuildArguments();
  const size_t count = boxes.size();
  args.buildQuality = triangles ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
  if (triangles) {
    boxes.resize(count * kSplitCapacity);  // room for the fragments
    args.splitPrimitive = splitTriangle;
    args.userPtr = const_cast<std::vector<gpu::GpuBvhTriangle>*>(triangles);
  }
  args.maxBranchingFactor = kWidth;
  args.maxDepth = kMaxDepth;
  args.minLeafSize = 1;
  args.maxLeafSize = leafSize;
  args.bvh = bvh;
  args.primitives = boxes.data();
  args.primitiveCount = count;
  args.primitiveArrayCapacity = boxes.size();
  args.createNode = createInner;
  args.setNodeChildren = setChildren;
  args.setNodeBounds = setBounds;
  args.createLeaf = createLeaf;
  const TreeNode* tree = static_cast<const TreeNode*>(rtcBuildBVH(&args));
  if (!tree || rtcGetDeviceError(device) != RTC_ERROR_NONE) {
    rtcReleaseBVH(bvh);
    throw std::runtime_error("BVH: Embree's builder failed on " + std::to_string(count) + " primitives");
  }
  Flattener flat{nodes, order, itemBase};
  if (tree->leaf) {  // the root must be a node: wrap a lone leaf
    uint32_t ref = flat.emit(tree);
    setChild(nodes[root], 0, lo, hi, ref);
  } else {
    nodes.pop_back();  // the tree's own root takes that index
    flat.emit(tree);
  }
  rtcReleaseBVH(bvh);
  return root;
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool isIdentity(const glm::mat4& m) { return m == glm::mat4(1.0f); }

RTCBuildPrimitive box(glm::vec3 lo, glm::vec3 hi, uint32_t id) {
  RTCBuildPrimitive p{};
  p.lower_x = lo.x;
  p.lower_y = lo.y;
  p.lower_z = lo.z;
  p.upper_x = hi.x;
  p.upper_y = hi.y;
  p.upper_z = hi.z;
  p.geomID = 0;
  p.primID = id;
  return p;
}

// A bottom level over the triangles of `parts` (a mesh, or every merged
// instance), appended to bvh.bottomNodes / bvh.triangles.
struct Part {
  const BvhMesh* mesh;
  glm::mat4 transform;  // applied to the vertices (identity for a mesh's own level)
  uint32_t instance;    // stored in the triangles: BVH_FROM_TOP_LEVEL for a mesh's own level
};

// The triangles of `parts` whose vertices are all finite, and their boxes (primID: the index of the triangle).
void collectTriangles(const BvhInput& input, std::span<const Part> parts, std::vector<gpu::GpuBvhTriangle>& candidates,
                      std::vector<RTCBuildPrimitive>& boxes) {
  for (const Part& part : parts) {
    for (const BvhGeometry& g : part.mesh->geometries) {
      for (uint32_t t = 0; t < g.triangleCount; ++t) {
        glm::vec3 v[3];
        bool valid = true;
        for (int k = 0; k < 3; ++k) {
          size_t index = size_t(g.firstIndex) + 3 * t + k;
          size_t vertex = index < input.indices.size() ? size_t(input.indices[index]) + g.vertexOffset : SIZE_MAX;
          if (vertex >= input.positions.size()) {
            valid = false;
            break;
          }
          v[k] = glm::vec3(part.transform * glm::vec4(input.positions[vertex], 1.0f));
          valid = valid && finite(v[k]);
        }
        if (!valid) continue;
        boxes.push_back(box(glm::min(v[0], glm::min(v[1], v[2])), glm::max(v[0], glm::max(v[1], v[2])),
                            uint32_t(candidates.size())));
        candidates.push_back({v[0], g.id, v[1] - v[0], t, v[2] - v[0], part.instance});
      }
    }
  }
}

// `splits`: spatial splits of the triangles (not for a level that is refit).
uint32_t buildBottom(RTCDevice device, const BvhInput& input, std::span<const Part> parts, bool splits, SceneBvh& bvh,
                     glm::vec3& lo, glm::vec3& hi) {
  std::vector<gpu::GpuBvhTriangle> candidates;
  std::vector<RTCBuildPrimitive> boxes;
  collectTriangles(input, parts, candidates, boxes);
  std::vector<uint32_t> order;
  uint32_t root = buildTree(device, std::move(boxes), kLeafSize, uint32_t(bvh.triangles.size()), bvh.bottomNodes, order,
                            lo, hi, splits ? &candidates : nullptr);
  for (uint32_t id : order) bvh.triangles.push_back(candidates[id]);
  return root;
}

gpu::GpuBvhInstance topInstance(const glm::mat4& worldFromObject, uint32_t root, uint32_t instance) {
  glm::mat4 inv = glm::inverse(worldFromObject);
  gpu::GpuBvhInstance out{};
  out.objectFromWorld0 = glm::vec4(inv[0][0], inv[1][0], inv[2][0], inv[3][0]);
  out.objectFromWorld1 = glm::vec4(inv[0][1], inv[1][1], inv[2][1], inv[3][1]);
  out.objectFromWorld2 = glm::vec4(inv[0][2], inv[1][2], inv[2][2], inv[3][2]);
  out.root = root;
  out.instance = instance;
  return out;
}

void transformBox(const glm::mat4& m, glm::vec3 lo, glm::vec3 hi, glm::vec3& outLo, glm::vec3& outHi) {
  outLo = glm::vec3(INFINITY);
  outHi = glm::vec3(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    glm::vec3 p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    glm::vec3 w = glm::vec3(m * glm::vec4(p, 1.0f));
    outLo = glm::min(outLo, w);
    outHi = glm::max(outHi, w);
  }
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

size_t maxTopNodes(size_t instanceCount) { return std::max<size_t>(1, 2 * (instanceCount + 1)); }
size_t maxTopInstances(size_t instanceCount) { return std::max<size_t>(1, instanceCount + 1); }

SceneBvh buildSceneBvh(const BvhInput& input) {
  auto start = std::chrono::steady_clock::now();
  EmbreeDevice embree;
  if (!embree.device) throw std::runtime_error("BVH: could not create an Embree device");
  SceneBvh bvh;
  bvh.meshRoot.assign(input.meshes.size(), gpu::BVH_NO_CHILD);
  bvh.meshMin.assign(input.meshes.size(), glm::vec3(0.0f));
  bvh.meshMax.assign(input.meshes.size(), glm::vec3(0.0f));
  bvh.merged.assign(input.instances.size(), 0);
  bvh.mergedTransforms.assign(input.instances.size(), glm::mat4(1.0f));

  std::vector<Part> mergedParts;
  std::vector<uint8_t> meshUsed(input.meshes.size(), 0);
  for (size_t i = 0; i < input.instances.size(); ++i) {
    const BvhInstance& inst = input.instances[i];
    if (inst.mesh >= input.meshes.size())
      throw std::runtime_error("BVH: instance " + std::to_string(i) + " names a missing mesh");
    if (!inst.movable && isIdentity(inst.worldFromObject)) {
      bvh.merged[i] = 1;
      bvh.mergedTransforms[i] = inst.worldFromObject;
      mergedParts.push_back({&input.meshes[inst.mesh], glm::mat4(1.0f), uint32_t(i)});
    } else {
      meshUsed[inst.mesh] = 1;
    }
  }
  if (!mergedParts.empty())
    bvh.mergedRoot = buildBottom(embree.device, input, mergedParts, true, bvh, bvh.mergedMin, bvh.mergedMax);
  bvh.meshFirstTriangle.assign(input.meshes.size(), 0);
  bvh.meshTriangleCount.assign(input.meshes.size(), 0);
  bvh.meshNodeCapacity.assign(input.meshes.size(), 0);
  for (size_t m = 0; m < input.meshes.size(); ++m) {
    if (!meshUsed[m]) continue;
    Part own{&input.meshes[m], glm::mat4(1.0f), gpu::BVH_FROM_TOP_LEVEL};
    const bool deformable = input.meshes[m].deformable;
    const size_t firstNode = bvh.bottomNodes.size(), firstTriangle = bvh.triangles.size();
    bvh.meshRoot[m] = buildBottom(embree.device, input, {&own, 1}, !deformable, bvh, bvh.meshMin[m], bvh.meshMax[m]);
    const size_t built = bvh.bottomNodes.size() - firstNode;
    // Room for a rebuild in another pose, whose tree may need a few more nodes (never referenced until then).
    bvh.bottomNodes.resize(firstNode + (deformable ? built + built / 2 + 1 : built), kEmptyNode);
    bvh.meshFirstTriangle[m] = uint32_t(firstTriangle);
    bvh.meshTriangleCount[m] = uint32_t(bvh.triangles.size() - firstTriangle);
    bvh.meshNodeCapacity[m] = uint32_t(bvh.bottomNodes.size() - firstNode);
  }
  bvh.bottomBuildMs = millisecondsSince(start);
  rebuildTopLevel(input.instances, bvh);
  return bvh;
}

MeshLevelSlots meshLevelSlots(const SceneBvh& bvh, uint32_t mesh) {
  return {bvh.meshRoot[mesh], bvh.meshFirstTriangle[mesh], bvh.meshTriangleCount[mesh], bvh.meshNodeCapacity[mesh]};
}

MeshLevel buildMeshLevel(const BvhInput& input, uint32_t mesh, const MeshLevelSlots& slots) {
  EmbreeDevice embree;
  if (!embree.device) throw std::runtime_error("BVH: could not create an Embree device");
  const Part own{&input.meshes[mesh], glm::mat4(1.0f), gpu::BVH_FROM_TOP_LEVEL};
  std::vector<gpu::GpuBvhTriangle> candidates;
  std::vector<RTCBuildPrimitive> boxes;
  collectTriangles(input, {&own, 1}, candidates, boxes);
  if (candidates.size() != slots.triangleCount) return {};
  MeshLevel level;
  std::vector<uint32_t> order;
  buildTree(embree.device, std::move(boxes), kLeafSize, slots.firstTriangle, level.nodes, order, level.lo, level.hi);
  if (level.nodes.size() > slots.nodeCapacity) return {};
  for (gpu::GpuBvhNode& n : level.nodes)  // built from node 0: the level starts at its root
    for (int k = 0; k < int(kWidth); ++k)
      if (n.child[k] != gpu::BVH_NO_CHILD && !(n.child[k] & gpu::BVH_LEAF_BIT)) n.child[k] += slots.root;
  level.nodes.resize(slots.nodeCapacity, kEmptyNode);
  level.triangles.reserve(order.size());
  for (uint32_t id : order) level.triangles.push_back(candidates[id]);
  return level;
}

void installMeshLevel(const MeshLevel& level, uint32_t mesh, SceneBvh& bvh) {
  std::copy(level.nodes.begin(), level.nodes.end(), bvh.bottomNodes.begin() + bvh.meshRoot[mesh]);
  std::copy(level.triangles.begin(), level.triangles.end(), bvh.triangles.begin() + bvh.meshFirstTriangle[mesh]);
  bvh.meshMin[mesh] = level.lo;
  bvh.meshMax[mesh] = level.hi;
}

LevelArrays levelArrays(const SceneBvh& bvh) { return {bvh.bottomNodes, 0, bvh.triangles, 0}; }

LevelArrays levelArrays(const MeshLevel& level, const MeshLevelSlots& slots) {
  return {level.nodes, slots.root, level.triangles, slots.firstTriangle};
}

bool rebuildMeshLevel(const BvhInput& input, uint32_t mesh, SceneBvh& bvh) {
  const MeshLevel level = buildMeshLevel(input, mesh, meshLevelSlots(bvh, mesh));
  if (level.nodes.empty()) return false;
  installMeshLevel(level, mesh, bvh);
  return true;
}

void rebuildTopLevel(std::span<const BvhInstance> instances, SceneBvh& bvh) {
  auto start = std::chrono::steady_clock::now();
  EmbreeDevice embree;
  if (!embree.device) throw std::runtime_error("BVH: could not create an Embree device");
  std::vector<gpu::GpuBvhInstance> items;
  std::vector<RTCBuildPrimitive> boxes;
  if (bvh.mergedRoot != gpu::BVH_NO_CHILD && bvh.mergedMin.x <= bvh.mergedMax.x) {
    boxes.push_back(box(bvh.mergedMin, bvh.mergedMax, uint32_t(items.size())));
    items.push_back(topInstance(glm::mat4(1.0f), bvh.mergedRoot, gpu::BVH_FROM_TOP_LEVEL));
  }
  for (size_t i = 0; i < instances.size() && i < bvh.merged.size(); ++i) {
    const BvhInstance& inst = instances[i];
    if (bvh.merged[i]) {
      if (inst.worldFromObject != bvh.mergedTransforms[i])
        throw std::runtime_error("BVH: instance " + std::to_string(i) +
                                 " was merged into the static level but moved; mark it movable before the build");
      continue;
    }
    uint32_t root = bvh.meshRoot[inst.mesh];
    if (root == gpu::BVH_NO_CHILD || bvh.meshMin[inst.mesh].x > bvh.meshMax[inst.mesh].x) continue;
    glm::vec3 lo, hi;
    transformBox(inst.worldFromObject, bvh.meshMin[inst.mesh], bvh.meshMax[inst.mesh], lo, hi);
    if (!finite(lo) || !finite(hi) || glm::determinant(glm::mat3(inst.worldFromObject)) == 0.0f) continue;
    boxes.push_back(box(lo, hi, uint32_t(items.size())));
    items.push_back(topInstance(inst.worldFromObject, root, uint32_t(i)));
  }
  bvh.topNodes.clear();
  std::vector<uint32_t> order;
  glm::vec3 lo, hi;
  buildTree(embree.device, std::move(boxes), 1, 0, bvh.topNodes, order, lo,
            hi);  // one instance per leaf (trace_bvh.glsl)
  bvh.topInstances.clear();
  for (uint32_t id : order) bvh.topInstances.push_back(items[id]);
  if (bvh.topInstances.empty())
    bvh.topInstances.push_back(gpu::GpuBvhInstance{});  // never referenced; keeps the buffer non-empty
  bvh.topBuildMs = millisecondsSince(start);
}

}  // namespace gi
