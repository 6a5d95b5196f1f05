// The light trees' nodes as their buffers hold them (GpuStoredLightNode, then the parents), read back as the
// shaders read them (lightNodeFromStored): shared by the punctual and emissive tables' tests.
#pragma once
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "shared/light_tree.h"

// Every node read back from words[at + 8i] and its parent from words[parentsAt + i] is nodes[i], bit for bit:
// the CPU's tests check the nodes the shaders walk.
inline void expectStoredNodesReadBack(const std::vector<uint32_t>& words, const std::vector<gpu::GpuLightNode>& nodes,
                                      size_t at, size_t parentsAt) {
  ASSERT_LE(parentsAt + nodes.size(), words.size());
  ASSERT_LE(at + nodes.size() * 8, parentsAt);
  for (size_t i = 0; i < nodes.size(); ++i) {
    gpu::GpuStoredLightNode stored;
    std::memcpy(&stored, words.data() + at + 8 * i, sizeof(stored));
    const gpu::GpuLightNode read = gpu::lightNodeFromStored(stored, words[parentsAt + i]);
    EXPECT_EQ(std::memcmp(&read, &nodes[i], sizeof(read)), 0)
        << "node " << i << ": axis (" << read.axis.x << ", " << read.axis.y << ", " << read.axis.z << ") against ("
        << nodes[i].axis.x << ", " << nodes[i].axis.y << ", " << nodes[i].axis.z << "), cosAim " << read.cosAim
        << " against " << nodes[i].cosAim;
  }
}
