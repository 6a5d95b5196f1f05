// Bad glTF input gets a sentence naming the file and the problem, never a
// crash; good input fills in what the file leaves out.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "gltf_loader.h"

namespace {

const std::string kData = GI_TEST_DATA;

struct Malformed {
  const char* file;
  const char* expect;  // a phrase the error must contain
};

const Malformed kMalformed[] = {
    {"missing_buffer.gltf", "does_not_exist.bin"},
    {"accessor_past_buffer_view.gltf", "reads past the end of its bufferView"},
    {"index_out_of_range.gltf", "out of range"},
    {"nan_position.gltf", "not finite"},
    {"inf_position.gltf", "not finite"},
    {"unsupported_required_extension.gltf", "EXT_made_up_compression"},
    {"bad_buffer_view_index.gltf", "no valid bufferView"},
    {"bad_material_index.gltf", "material 3"},
    {"node_cycle.gltf", "cycle"},
    {"bad_mesh_index.gltf", "mesh 4"},
    {"position_wrong_type.gltf", "VEC3"},
    {"missing_position.gltf", "no POSITION"},
    {"buffer_shorter_than_declared.gltf", "uri"},
    {"buffer_view_out_of_range.gltf", "past the end of its buffer"},
    {"not_json.gltf", "parse error"},
    {"empty_file.gltf", "empty"},
    {"wrong_version.gltf", "asset.version"},
    // An image URI naming a directory (the fuzzer's find: tinygltf's own reader allocated -1 bytes).
    {"image_uri_is_a_directory.gltf", "image 0 ('.') could not be decoded"},
};

}  // namespace

TEST(GltfLoader, EveryMalformedFileGetsANamedError) {
  size_t checked = 0;
  for (const Malformed& m : kMalformed) {
    std::string path = kData + "/malformed/" + m.file;
    engine::Scene scene;
    std::string error;
    EXPECT_FALSE(engine::loadGltf(path, scene, error)) << m.file;
    EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << "error must start with the file name: " << error;
    EXPECT_NE(error.find(m.expect), std::string::npos) << m.file << ": " << error;
    EXPECT_TRUE(scene.instances.empty());
    ++checked;
  }
  // The corpus on disk and the table above must not drift apart.
  size_t onDisk = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kData + "/malformed"))
    onDisk += entry.path().extension() == ".gltf";
  EXPECT_EQ(onDisk, checked);
}

TEST(GltfLoader, MissingFileIsNamed) {
  engine::Scene scene;
  std::string error;
  EXPECT_FALSE(engine::loadGltf("/no/such/scene.gltf", scene, error));
  EXPECT_EQ(error, "/no/such/scene.gltf: file not found");
}

TEST(GltfLoader, FillsInNormalsCameraStripsAndHierarchy) {
  engine::Scene scene;
  std::string error;
  ASSERT_TRUE(engine::loadGltf(kData + "/valid/no_normals_no_camera.gltf", scene, error)) << error;
  ASSERT_EQ(scene.instances.size(), 2u);
  ASSERT_EQ(scene.cameras.size(), 1u);  // a default camera was added
  EXPECT_EQ(scene.cameras[0].name, "default");
  for (const glm::vec3& n : scene.normals) EXPECT_NEAR(n.y, 1.0f, 1e-5f);  // generated, facing +Y (CCW from above)
  // The strip (4 indices) became 2 triangles.
  EXPECT_EQ(scene.primitives[1].indexCount, 6u);
  // The child node inherits its parent's transform and adds its own translation.
  EXPECT_FLOAT_EQ(scene.instances[1].worldFromObject[3].y, 2.0f);
  engine::Bounds b = scene.worldBounds();
  EXPECT_FLOAT_EQ(b.max.y, 2.0f);
  // The camera looks at the scene: the bounds centre is in front of it (view −Z).
  glm::vec3 centreInView = glm::vec3(glm::inverse(scene.cameras[0].worldFromView) * glm::vec4(b.center(), 1.0f));
  EXPECT_LT(centreInView.z, 0.0f);
}

TEST(GltfLoader, SharedScenesLoadWithLightsAndCameras) {
  engine::Scene scene;
  std::string error;
  ASSERT_TRUE(engine::loadGltf(std::string(GI_SHARED_SCENES) + "/conference-ward/conference-ward.gltf", scene, error))
      << error;
  EXPECT_EQ(scene.lights.size(), 4u);
  EXPECT_EQ(scene.lights[0].type, engine::LightType::Point);
  EXPECT_NEAR(scene.lights[0].intensity.y, 4.0f * 0.93f, 1e-5f);  // colour × intensity, W/sr as-is
  EXPECT_FALSE(scene.hasEmissiveGeometry());
  ASSERT_TRUE(engine::loadGltf(std::string(GI_SHARED_SCENES) + "/cornell-simple/cornell_simple.gltf", scene, error))
      << error;
  EXPECT_TRUE(scene.hasEmissiveGeometry());
  EXPECT_TRUE(scene.lights.empty());
  bool found = false;
  for (const engine::Material& m : scene.materials)
    if (m.name == "light") {
      EXPECT_FLOAT_EQ(m.emission.x, 10.0f);  // emissiveFactor × KHR_materials_emissive_strength
      found = true;
    }
  EXPECT_TRUE(found);
  // The two boxes share one mesh through node transforms: 9 instances, 7 meshes.
  EXPECT_EQ(scene.instances.size(), 8u);
  EXPECT_EQ(scene.meshes.size(), 7u);
}
