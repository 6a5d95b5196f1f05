// What a host that fills only what it must gets from the scene description's defaults (issue 35: a
// default must never silently change the image): a white dielectric, no glossy lobe, no emission.
#include <gtest/gtest.h>

#include "quad_contents.h"
#include "scene/scene_tables.h"

TEST(SceneDefaults, AMaterialWithOnlyItsBaseColourIsARoughDielectric) {
  QuadContents quad;
  quad.material.baseColor[0] = 0.8f;  // all a host sets
  gi::PackedScene packed;
  ASSERT_EQ(gi::packScene(quad.contents(), packed), "");
  ASSERT_EQ(packed.materials.size(), 1u);
  const gpu::GpuMaterial& g = packed.materials[0];
  EXPECT_EQ(g.metallic, 0.0f) << "a dielectric: glTF's metallicFactor default of 1 is a loader's to set";
  EXPECT_EQ(g.roughness, 1.0f);
  EXPECT_EQ(g.flags & gpu::MATERIAL_FLAG_GLOSSY, 0u) << "no GGX lobe";
  EXPECT_EQ(g.flags & gpu::MATERIAL_FLAG_EMISSIVE, 0u);
  EXPECT_FALSE(packed.hasGlossyMaterials);
  EXPECT_EQ(g.baseColor, glm::vec4(0.8f, 1.0f, 1.0f, 1.0f));
}
