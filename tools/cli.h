// Command-line parsing shared by the tools: `--name value` and `--flag`
// options, strict typed getters, and one usage message. Every problem is a
// sentence in `error`; the caller prints it with the usage and exits 2.
#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "context.h"
#include "scene.h"
#include "sky.h"

namespace gi {
struct SceneDesc;
}

namespace cli {

struct Option {
  const char* name;       // without the leading dashes
  const char* valueHint;  // nullptr for a flag
  const char* help;
};

struct Args {
  std::map<std::string, std::string> values;
  bool has(const std::string& name) const { return values.count(name) > 0; }
};

bool parse(int argc, char** argv, std::span<const Option> options, Args& args, std::string& error);
std::string usage(const char* program, const char* synopsis, std::span<const Option> options);

// Typed access; each returns false with a sentence in `error` when the value is malformed or out of range.
bool getUint(const Args& args, const std::string& name, uint32_t fallback, uint32_t min, uint32_t max, uint32_t& out,
             std::string& error);
bool getSize(const Args& args, const std::string& name, uint32_t fallbackW, uint32_t fallbackH, uint32_t& w,
             uint32_t& h, std::string& error);
bool getChoice(const Args& args, const std::string& name, const std::string& fallback,
               std::span<const char* const> choices, std::string& out, std::string& error);
std::vector<std::string> splitList(const std::string& text, char separator = ',');

// --traversal, shared by gi-render, gi-bench and the demo.
inline constexpr Option kTraversalOption{
    "traversal", "NAME",
    "auto (default), rayquery or compute: how rays are traced (auto: compute on CPU devices and on devices "
    "without ray queries, where it is faster or the only way)"};
bool getTraversal(const Args& args, engine::Traversal& traversal, std::string& error);

// --sky, shared likewise: the light of rays that leave the scene (default black).
inline constexpr Option kSkyOption{
    "sky", "R,G,B|FILE",
    "light from beyond the scene: a constant radiance R,G,B in W/(sr·m²), or an equirectangular .exr/.pfm map "
    "(+Y up, −Z at its centre column); default black"};
// Leaves `sky` black when --sky is absent.
bool getSky(const Args& args, engine::Sky& sky, std::string& error);
// A short name of the sky for file names and cache keys: "" when black.
std::string skyKey(const engine::Sky& sky);

// --point-lights, shared by gi-render and gi-bench: the many-light scenes of issue 31.
inline constexpr Option kPointLightsOption{
    "point-lights", "N",
    "replace the scene's point lights by N of the same total intensity on a grid at their mean height "
    "(engine/light_grid.h; 1 to 65536)"};
// Applies --point-lights to `scene` (nothing when absent); false with `error` when it cannot.
bool applyPointLights(const Args& args, engine::Scene& scene, std::string& error);
// A short name of --point-lights for file names and cache keys: "" when absent.
std::string pointLightsKey(const Args& args);

// --light-sampler, shared likewise (gi::SceneCreateDesc::lightSampler).
inline constexpr Option kLightSamplerOption{
    "light-sampler", "NAME",
    "all: a shadow ray to every punctual light at every path vertex; power: one light a vertex, picked by its "
    "power; tree (default): every directional light and one point or spot light from each subtree of a cut "
    "of a tree over them (--light-tree-cut), picked by power, distance and angle: exact with no more lights "
    "than the cut has subtrees (power and tree cost the same at any light count)"};
// --light-tree-cut, shared likewise (gi::SceneCreateDesc::lightTreeCut).
inline constexpr Option kLightTreeCutOption{
    "light-tree-cut", "N",
    "with --light-sampler tree: shadow rays a vertex for the point and spot lights, one from each of N subtrees "
    "(exact with no more lights than N; 1 to 64, default 4)"};
// Sets `sampler` (gpu::LIGHT_SAMPLER_*) from --light-sampler and `treeCut` from --light-tree-cut (each
// left as is when absent); false with `error` when either is not one they take.
bool getLightSampler(const Args& args, uint32_t& sampler, uint32_t& treeCut, std::string& error);
// A short name of the light sampler for file names and cache keys: "" where it traces every light exactly
// (`facts`, the scene's gi::SceneDesc: picksPunctualLights is false), else its name, and the tree's cut. The
// references of every sampler converge to the same image: the key keeps a noisier one apart.
std::string lightSamplerKey(const engine::Scene& scene, const gi::SceneDesc& facts);

}  // namespace cli
