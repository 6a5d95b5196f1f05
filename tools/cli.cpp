#include "cli.h"

#include "gi/gi.h"
#include "gi/scene.h"
#include "shared/gpu_scene.h"

#include "light_grid.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace cli {

bool parse(int argc, char** argv, std::span<const Option> options, Args& args, std::string& error) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0) {
      error = "unexpected argument '" + arg + "'";
      return false;
    }
    std::string name = arg.substr(2);
    auto opt = std::find_if(options.begin(), options.end(), [&](const Option& o) { return name == o.name; });
    if (opt == options.end()) {
      error = "unknown option '" + arg + "'";
      return false;
    }
    if (opt->valueHint) {
      if (i + 1 >= argc) {
        error = "option '" + arg + "' needs a value (" + opt->valueHint + ")";
        return false;
      }
      // A repeated option accumulates: "--set a=1 --set b=2" reads as "a=1,b=2".
      std::string& slot = args.values[name];
      slot = slot.empty() ? std::string(argv[++i]) : slot + "," + argv[++i];
    } else {
      args.values[name].assign(1, '1');  // (a literal here trips GCC 12's -Wrestrict false positive)
    }
  }
  return true;
}

std::string usage(const char* program, const char* synopsis, std::span<const Option> options) {
  std::string text = std::string("usage: ") + program + " " + synopsis + "\n";
  for (const Option& o : options) {
    std::string left = std::string("  --") + o.name + (o.valueHint ? std::string(" ") + o.valueHint : "");
    left.resize(std::max<size_t>(left.size() + 1, 30), ' ');
    text += left + o.help + "\n";
  }
  return text;
}

bool getUint(const Args& args, const std::string& name, uint32_t fallback, uint32_t min, uint32_t max, uint32_t& out,
             std::string& error) {
  auto it = args.values.find(name);
  if (it == args.values.end()) {
    out = fallback;
    return true;
  }
  const std::string& s = it->second;
  char* end = nullptr;
  errno = 0;
  unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (s.empty() || s[0] == '-' || *end != '\0' || errno != 0 || v < min || v > max) {
    error = "--" + name + " must be a whole number from " + std::to_string(min) + " to " + std::to_string(max) +
            ", not '" + s + "'";
    return false;
  }
  out = uint32_t(v);
  return true;
}

bool getSize(const Args& args, const std::string& name, uint32_t fallbackW, uint32_t fallbackH, uint32_t& w,
             uint32_t& h, std::string& error) {
  auto it = args.values.find(name);
  if (it == args.values.end()) {
    w = fallbackW;
    h = fallbackH;
    return true;
  }
  unsigned long width = 0, height = 0;
  char extra = 0;
  if (std::sscanf(it->second.c_str(), "%lux%lu%c", &width, &height, &extra) != 2 || width < 1 || height < 1 ||
      width > 16384 || height > 16384) {
    error = "--" + name + " must look like 320x180 (1 to 16384 per side), not '" + it->second + "'";
    return false;
  }
  w = uint32_t(width);
  h = uint32_t(height);
  return true;
}

bool getChoice(const Args& args, const std::string& name, const std::string& fallback,
               std::span<const char* const> choices, std::string& out, std::string& error) {
  auto it = args.values.find(name);
  out = it == args.values.end() ? fallback : it->second;
  for (const char* c : choices)
    if (out == c) return true;
  error = "--" + name + " must be one of";
  for (const char* c : choices) error += std::string(" ") + c;
  error += ", not '" + out + "'";
  return false;
}

std::vector<std::string> splitList(const std::string& text, char separator) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find(separator, start);
    if (end == std::string::npos) end = text.size();
    out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

bool getSky(const Args& args, engine::Sky& sky, std::string& error) {
  auto it = args.values.find("sky");
  return it == args.values.end() || engine::parseSky(it->second, sky, error);
}

std::string skyKey(const engine::Sky& sky) {
  if (!sky.enabled()) return "";
  char text[96];
  std::snprintf(text, sizeof(text), "_sky%g-%g-%g", sky.radiance.x, sky.radiance.y, sky.radiance.z);
  std::string key = text;
  if (sky.hasMap()) {
    // The map's name and a checksum of its texels, so another map of the same name is another key.
    uint64_t hash = 1469598103934665603ull;
    for (float v : sky.map.pixels) {
      uint32_t bits;
      std::memcpy(&bits, &v, 4);
      hash = (hash ^ bits) * 1099511628211ull;
    }
    std::snprintf(text, sizeof(text), "_%016llx", static_cast<unsigned long long>(hash));
    key.append("_").append(std::filesystem::path(sky.mapPath).stem().string()).append(text);
  }
  return key;
}

bool applyPointLights(const Args& args, engine::Scene& scene, std::string& error) {
  if (!args.has("point-lights")) return true;
  uint32_t count = 0;
  if (!getUint(args, "point-lights", 0, 1, 65536, count, error)) return false;
  return engine::spreadPointLights(scene, count, error);
}

std::string pointLightsKey(const Args& args) {
  return args.has("point-lights") ? "_pl" + args.values.at("point-lights") : "";
}

bool getLightSampler(const Args& args, uint32_t& sampler, uint32_t& treeCut, std::string& error) {
  if (args.has("light-tree-cut") && !getUint(args, "light-tree-cut", treeCut, 1, 64, treeCut, error)) return false;
  auto it = args.values.find("light-sampler");
  if (it == args.values.end()) return true;
  for (uint32_t i = 0; i < std::size(gi::kLightSamplerNames); ++i)
    if (it->second == gi::kLightSamplerNames[i]) {
      sampler = i;
      return true;
    }
  error = "--light-sampler must be all, power or tree, not '" + it->second + "'";
  return false;
}

std::string lightSamplerKey(const engine::Scene& scene, const gi::SceneDesc& facts) {
  if (!gi::picksPunctualLights(facts)) return "";
  const std::string name = std::string("_") + gi::kLightSamplerNames[scene.lightSampler];
  return scene.lightSampler == gpu::LIGHT_SAMPLER_TREE ? name + std::to_string(scene.lightTreeCut) : name;
}

bool getTraversal(const Args& args, engine::Traversal& traversal, std::string& error) {
  auto it = args.values.find("traversal");
  if (it == args.values.end() || engine::parseTraversal(it->second, traversal)) return true;
  error = "--traversal must be one of auto, rayquery, compute, not '" + it->second + "'";
  return false;
}

}  // namespace cli
