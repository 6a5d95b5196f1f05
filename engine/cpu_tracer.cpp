#include "cpu_tracer.h"

#include "shared/ray_bench.h"

#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

namespace engine {

struct CpuTracer {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  struct Source {
    uint32_t instance, geometry;
  };
  std::vector<Source> sources;  // per Embree geometry id
};

void CpuTracerDeleter::operator()(CpuTracer* t) const {
  if (!t) return;
  if (t->scene) rtcReleaseScene(t->scene);
  if (t->device) rtcReleaseDevice(t->device);
  delete t;
}

CpuTracerPtr createCpuTracer(const Scene& scene, std::string& error) {
  CpuTracerPtr tracer(new CpuTracer);
  tracer->device = rtcNewDevice(nullptr);
  if (!tracer->device) {
    error = "Embree: could not create a device";
    return nullptr;
  }
  tracer->scene = rtcNewScene(tracer->device);
  rtcSetSceneFlags(tracer->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(tracer->scene, RTC_BUILD_QUALITY_HIGH);
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const Mesh& mesh = scene.meshes[inst.mesh];
    for (uint32_t p = mesh.firstPrimitive; p < mesh.firstPrimitive + mesh.primitiveCount; ++p) {
      const Primitive& prim = scene.primitives[p];
      if (prim.indexCount < 3 || prim.vertexCount == 0) continue;
      RTCGeometry g = rtcNewGeometry(tracer->device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), prim.vertexCount));
      for (uint32_t k = 0; k < prim.vertexCount; ++k) {
        glm::vec3 w = glm::vec3(inst.worldFromObject * glm::vec4(scene.positions[prim.vertexOffset + k], 1.0f));
        v[3 * k] = w.x;
        v[3 * k + 1] = w.y;
        v[3 * k + 2] = w.z;
      }
      auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(uint32_t), prim.indexCount / 3));
      for (uint32_t k = 0; k < prim.indexCount / 3 * 3; ++k) idx[k] = scene.indices[prim.firstIndex + k];
      rtcCommitGeometry(g);
      uint32_t id = rtcAttachGeometry(tracer->scene, g);
      rtcReleaseGeometry(g);
      if (tracer->sources.size() <= id) tracer->sources.resize(id + 1);
      tracer->sources[id] = {i, p};
    }
  }
  rtcCommitScene(tracer->scene);
  if (rtcGetDeviceError(tracer->device) != RTC_ERROR_NONE) {
    error = scene.sourcePath + ": Embree's scene build failed";
    return nullptr;
  }
  return tracer;
}

namespace {

RTCRayHit makeRayHit(glm::vec3 o, glm::vec3 d, float tMin, float tMax) {
  RTCRayHit rh{};
  rh.ray.org_x = o.x;
  rh.ray.org_y = o.y;
  rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x;
  rh.ray.dir_y = d.y;
  rh.ray.dir_z = d.z;
  rh.ray.tnear = tMin;
  rh.ray.tfar = tMax;
  rh.ray.mask = 0xffffffffu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

CpuHit cpuTraceClosest(const CpuTracer& tracer, glm::vec3 origin, glm::vec3 direction, float tMin, float tMax) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh = makeRayHit(origin, direction, tMin, tMax);
  rtcIntersect1(tracer.scene, &context, &rh);
  CpuHit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.t = rh.ray.tfar;
  hit.instance = tracer.sources[rh.hit.geomID].instance;
  hit.geometry = tracer.sources[rh.hit.geomID].geometry;
  hit.triangle = rh.hit.primID;
  hit.barycentrics = {rh.hit.u, rh.hit.v};
  hit.geometricNormal = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
  return hit;
}

bool cpuTraceVisible(const CpuTracer& tracer, glm::vec3 origin, glm::vec3 direction, float tMin, float tMax) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = makeRayHit(origin, direction, tMin, tMax).ray;
  rtcOccluded1(tracer.scene, &context, &ray);
  return ray.tfar >= 0.0f;  // Embree sets tfar to −inf when occluded
}

namespace {

glm::vec3 cosineSample(glm::vec3 n, float u1, float u2) {
  glm::vec3 t = std::abs(n.x) > 0.5f ? glm::normalize(glm::cross(n, glm::vec3(0, 1, 0)))
                                     : glm::normalize(glm::cross(n, glm::vec3(1, 0, 0)));
  glm::vec3 b = glm::cross(n, t);
  float r = std::sqrt(u1), phi = 6.2831853f * u2;
  return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1.0f - u1)) * n);
}

// Rays traced and seconds taken by one pass over the image on every thread.
struct Pass {
  uint64_t rays = 0;
  double seconds = 0.0;
};

Pass runPass(const CpuTracer& tracer, const Scene& scene, const gpu::GpuCamera& camera, uint32_t paths, uint32_t kind) {
  const uint32_t w = uint32_t(camera.imageSize.x), h = uint32_t(camera.imageSize.y);
  Bounds bounds = scene.worldBounds();
  std::atomic<uint64_t> rays{0};
  std::atomic<uint32_t> nextRow{0};
  auto worker = [&] {
    uint64_t local = 0;
    for (uint32_t y = nextRow++; y < h; y = nextRow++) {
      for (uint32_t x = 0; x < w; ++x) {
        std::minstd_rand rng(1u + x + y * w);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        for (uint32_t i = 0; i < paths; ++i) {
          glm::vec3 dir = gpu::giCameraRayDirection(camera, glm::vec2(float(x) + u(rng), float(y) + u(rng)));
          CpuHit hit = cpuTraceClosest(tracer, camera.position, dir, 0.0f, 1e30f);
          ++local;
          if (hit.t < 0.0f || kind == gpu::RB_KIND_PRIMARY) continue;
          glm::vec3 n = glm::normalize(hit.geometricNormal);
          if (glm::dot(n, dir) > 0.0f) n = -n;
          glm::vec3 p = camera.position + hit.t * dir + 1e-4f * n;
          if (kind == gpu::RB_KIND_DIFFUSE) {
            cpuTraceClosest(tracer, p, cosineSample(n, u(rng), u(rng)), 0.0f, 1e30f);
          } else {
            glm::vec3 target = glm::mix(bounds.min, bounds.max, glm::vec3(u(rng), u(rng), u(rng)));
            float distance = glm::length(target - p);
            if (distance > 0.0f) cpuTraceVisible(tracer, p, (target - p) / distance, 0.0f, distance);
          }
          ++local;
        }
      }
    }
    rays += local;
  };
  auto start = std::chrono::steady_clock::now();
  std::vector<std::thread> threads;
  for (unsigned t = 0; t < std::max(1u, std::thread::hardware_concurrency()); ++t) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  return {rays.load(), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
}

}  // namespace

CpuRayRates measureCpuRayRates(const CpuTracer& tracer, const Scene& scene, const gpu::GpuCamera& camera,
                               uint32_t pathsPerPixel) {
  Pass primary = runPass(tracer, scene, camera, pathsPerPixel, gpu::RB_KIND_PRIMARY);
  auto extra = [&](uint32_t kind) {
    Pass p = runPass(tracer, scene, camera, pathsPerPixel, kind);
    double rays = double(p.rays) - double(primary.rays), seconds = p.seconds - primary.seconds;
    return rays > 0.0 && seconds > 0.0 ? rays / seconds * 1e-6 : 0.0;
  };
  CpuRayRates rates;
  rates.primary = primary.seconds > 0.0 ? double(primary.rays) / primary.seconds * 1e-6 : 0.0;
  rates.diffuse = extra(gpu::RB_KIND_DIFFUSE);
  rates.shadow = extra(gpu::RB_KIND_SHADOW);
  return rates;
}

}  // namespace engine
