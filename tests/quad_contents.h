// One quad (two triangles), its material, one instance and one point light as gi::SceneContents: the
// smallest scene a host can hand the module, for the scene API's tests.
#pragma once
#include "gi/scene.h"

struct QuadContents {
  float positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  float normals[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  uint32_t indices[6] = {0, 1, 2, 0, 2, 3};
  gi::PrimitiveDesc primitive{0, 6, 0, 4, 0};
  gi::MeshDesc mesh;
  gi::MaterialDesc material;
  gi::InstanceDesc instance;
  gi::LightDesc light;
  // Points into this object: keep it alive while the contents are used.
  gi::SceneContents contents() {
    mesh.positions = positions;
    mesh.normals = normals;
    mesh.vertexCount = 4;
    mesh.indices = indices;
    mesh.indexCount = 6;
    mesh.primitives = std::span(&primitive, 1);
    gi::SceneContents c;
    c.meshes = std::span(&mesh, 1);
    c.materials = std::span(&material, 1);
    c.instances = std::span(&instance, 1);
    c.lights = std::span(&light, 1);
    return c;
  }
};
