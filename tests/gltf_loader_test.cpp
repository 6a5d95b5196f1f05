// Bad glTF input gets a sentence naming the file and the problem, never a
// crash; good input fills in what the file leaves out.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "gltf_loader.h"
#include "run_process.h"

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
};

int runTool(const std::string& args, std::string& output) { return runProcess(GI_RENDER_BINARY, args, output); }

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
  ASSERT_TRUE(engine::loadGltf(std::string(GI_SHARED_SCENES) + "/conference-ward/conference-ward.gltf", scene, error)) << error;
  EXPECT_EQ(scene.lights.size(), 4u);
  EXPECT_EQ(scene.lights[0].type, engine::LightType::Point);
  EXPECT_NEAR(scene.lights[0].intensity.y, 4.0f * 0.93f, 1e-5f);  // colour × intensity, W/sr as-is
  EXPECT_FALSE(scene.hasEmissiveGeometry());
  ASSERT_TRUE(engine::loadGltf(std::string(GI_SHARED_SCENES) + "/cornell-simple/cornell_simple.gltf", scene, error)) << error;
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

TEST(GiRenderTool, BadInputExitsWithASentence) {
  std::string out;
  EXPECT_EQ(runTool("--scene " + kData + "/malformed/index_out_of_range.gltf", out), 1) << out;
  EXPECT_NE(out.find("index_out_of_range.gltf: "), std::string::npos) << out;
  EXPECT_EQ(runTool("--scene /no/such.gltf", out), 1) << out;
  EXPECT_EQ(runTool("--bogus 1", out), 2) << out;
  EXPECT_NE(out.find("usage:"), std::string::npos);
  EXPECT_EQ(runTool("--scene x.gltf --size 0x10", out), 2) << out;
  EXPECT_EQ(runTool("--scene x.gltf --spp -3", out), 2) << out;
  EXPECT_EQ(runTool("--scene x.gltf --aov colour", out), 2) << out;
  EXPECT_EQ(runTool("--scene x.gltf --method magic", out), 2) << out;
  EXPECT_EQ(runTool("--scene", out), 2) << out;
}

TEST(GiRenderTool, RendersWithValidationAndWritesStats) {
  std::string dir = std::filesystem::temp_directory_path() / "gi_render_test";
  std::filesystem::create_directories(dir);
  std::string out;
  int rc = runTool("--scene " + std::string(GI_SHARED_SCENES) +
                       "/cornell-box-mcguire/CornellBox-Original.gltf --size 16x16 --spp 2 --max-bounces 2 --validation"
                       " --aov indirect --out " + dir + "/i.pfm --stats " + dir + "/s.json",
                   out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/i.pfm"));
  std::ifstream f(dir + "/s.json");
  nlohmann::json j = nlohmann::json::parse(f);
  EXPECT_EQ(j["width"], 16);
  EXPECT_EQ(j["spp"], 2);
  EXPECT_EQ(j["max_bounces"], 2);
  EXPECT_GT(j["rays"].get<uint64_t>(), 16u * 16u * 2u);
  EXPECT_GT(j["passes_ms"]["path_trace"].get<double>(), 0.0);
  EXPECT_EQ(j["validation_messages"], 0);
  EXPECT_TRUE(j.contains("device"));
  EXPECT_TRUE(j.contains("wall_seconds"));
}
