// A deformable mesh's compute-BVH level kept worth tracing (SceneCreateDesc::rebuildCostRatio): its
// surface-area cost measured after its updates against its cost when built, and past the ratio rebuilt,
// in the update or on a worker thread (SceneCreateDesc::rebuildOffThread). Meshes posed by device streams
// are measured on positions read back now and then, one mesh at a time and without a wait: an update
// copies them into a host-visible buffer and sets an event after the copy, and a later update of the
// mesh that finds the event set takes them. A scene for ray queries alone keeps its deformable levels on
// the CPU for this measure alone (never uploaded): there a rebuild builds the BLAS anew.
#pragma once
#include <cstdint>

#include "scene/scene.h"

namespace gi {

// What an update does to its mesh's level beyond writing the vertices.
struct LevelUpdate {
  bool nodesBuilt = false;  // its nodes were built for this update's pose and written: no refit
  bool blasBuild = false;   // its BLAS is built anew rather than updated (ray queries)
};

// After an update with CPU arrays (the new positions in s.packed): a finished off-thread rebuild of the
// level installed, or the level measured, and past the ratio rebuilt here or started off thread. Nodes
// and the refit order written into `cmd` as transfers, made visible by the caller's barrier.
LevelUpdate rebuildDegradedLevel(Scene& s, VkCommandBuffer cmd, uint32_t mesh);

// The same for an update with device streams, before its refit: a finished rebuild installed, or the
// positions an earlier update read back taken into s.packed and measured. Nodes built from those are an
// earlier pose's: the caller refits them (nodesBuilt stays false).
LevelUpdate followDeviceLevel(Scene& s, VkCommandBuffer cmd, uint32_t mesh);
// After an update with device streams made its positions visible: their copy into the read-back buffer
// and the event after it, unless positions are on their way already or a rebuild runs.
void recordPositionsReadback(Scene& s, VkCommandBuffer cmd, uint32_t mesh);

// The read-back buffer (the largest deformable mesh's positions) and its event; and their end.
vk::Status createPositionsReadback(Scene& s);
void destroyPositionsReadback(Scene& s);

}  // namespace gi
