// libFuzzer target for the glTF loader: any bytes, as a .gltf or (with the
// binary magic) a .glb, must give a scene or a named error — no crash, no
// hang, no sanitizer report. Run by scripts/fuzz-gltf.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The loader reads files (and resolves buffer URIs next to them), so each input becomes one.
  static const std::string base = "/tmp/gi_gltf_fuzz_" + std::to_string(getpid());
  bool binary = size >= 4 && data[0] == 'g' && data[1] == 'l' && data[2] == 'T' && data[3] == 'F';
  std::string path = base + (binary ? ".glb" : ".gltf");
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  engine::Scene scene;
  std::string error;
  if (!engine::loadGltf(path, scene, error) && error.empty()) __builtin_trap();  // an error must say what went wrong
  std::remove(path.c_str());
  return 0;
}
