// Shared set-up for tests that drive the GI module: a pixel-centre reference
// (what the raster G-buffer sees) and a module session that fails the test
// when it cannot be created.
#pragma once
#include "gpu_test.h"
#include "module_session.h"

inline engine::ReferenceImages pixelCentreReference(const engine::Context& ctx, const LoadedScene& s,
                                                    const gpu::GpuCamera& cam, uint32_t bounces, uint32_t spp) {
  engine::ReferenceSettings settings;
  settings.maxBounces = bounces;
  settings.pixelJitter = false;  // the module sees the raster G-buffer: pixel centres
  return engine::renderReference(ctx, s.gpu, cam, settings, spp, 256).images;
}

// Use as ASSERT_NO_FATAL_FAILURE(openSession(...)).
inline void openSession(const engine::Context& ctx, const LoadedScene& s, VkExtent2D size, const gi::Settings& settings,
                        tools::ModuleSession& session, const gi::ModuleDesc* desc = nullptr) {
  std::string error;
  ASSERT_TRUE(tools::createModuleSession(ctx, s.gpu, size, settings, session, error, desc)) << error;
}
