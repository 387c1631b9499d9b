// Animation sampling (glTF 2.0 sec. 3.11 "Animations" and appendix C "Interpolation"). A sampler's input holds the
// key times t_0 <= ... <= t_{n-1}; its output one value per key (STEP, LINEAR) or three (CUBICSPLINE: in-tangent a_k,
// value v_k, out-tangent b_k). Between t_k and t_{k+1}, with s = (t - t_k) / (t_{k+1} - t_k) and d = t_{k+1} - t_k:
//   LINEAR       v_k + s (v_{k+1} - v_k), rotations slerp(v_k, v_{k+1}, s) along the shorter arc
//   CUBICSPLINE  (2s^3 - 3s^2 + 1) v_k + d (s^3 - 2s^2 + s) b_k + (-2s^3 + 3s^2) v_{k+1} + d (s^3 - s^2) a_{k+1},
//                rotations normalised afterwards
// Outside [t_0, t_{n-1}] the first or last value holds (the spec leaves it to the implementation).
#include "host/scene/gltf_animation.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace penumbra::detail {
namespace {

enum class Interpolation { Step, Linear, Cubic };

struct Sampler {
  std::vector<float> times;
  std::vector<float> values;  // keys x (3 if cubic) x width
  Interpolation interpolation = Interpolation::Linear;
  int width = 0;  // numbers per value: 3 (translation, scale), 4 (rotation), morph target count (weights)
};

Interpolation interpolationOf(const GltfContext& ctx, const std::string& what, const std::string& name) {
  if (name.empty() || name == "LINEAR") return Interpolation::Linear;
  if (name == "STEP") return Interpolation::Step;
  if (name == "CUBICSPLINE") return Interpolation::Cubic;
  failGltf(ctx, fmt::format("{}: unknown interpolation '{}' (LINEAR, STEP or CUBICSPLINE)", what, name));
}

Sampler readSampler(const GltfContext& ctx, const std::string& what, const tinygltf::AnimationSampler& s,
                    const std::string& path, int width) {
  Sampler out;
  out.width = width;
  out.interpolation = interpolationOf(ctx, what, s.interpolation);
  out.times = readFloats(ctx, s.input, 1, false, "animation sampler input");
  for (size_t k = 0; k < out.times.size(); ++k)
    if (!std::isfinite(out.times[k]) || (k > 0 && out.times[k] <= out.times[k - 1]))  // sec. 5.8: strictly
      failGltf(ctx, fmt::format("{}: input time {} ({}) is not finite or does not increase", what, k, out.times[k]));
  // Rotations and weights may be normalized integers (sec. 3.11, "Animations"); translations and scales are floats.
  const bool vector = path == "translation" || path == "scale";
  const int components = path == "weights" ? 1 : width;
  out.values = readFloats(ctx, s.output, components, !vector, "animation sampler output");
  const size_t perKey = static_cast<size_t>(width) * (out.interpolation == Interpolation::Cubic ? 3 : 1);
  if (out.values.size() != out.times.size() * perKey)
    failGltf(ctx, fmt::format("{}: output has {} numbers; {} keys of '{}' ({} numbers each) need {}", what,
                              out.values.size(), out.times.size(), path, perKey, out.times.size() * perKey));
  for (size_t i = 0; i < out.values.size(); ++i)  // named here, not as the world transform it would spoil
    if (!std::isfinite(out.values[i]))
      failGltf(ctx, fmt::format("{}: output key {} of '{}' holds {} (component {})", what, i / perKey, path,
                                out.values[i], i % perKey));
  return out;
}

// Component c of key k's value (cubic: the middle of the three).
double value(const Sampler& s, size_t k, int c) {
  const size_t w = static_cast<size_t>(s.width);
  return s.interpolation == Interpolation::Cubic ? s.values[(3 * k + 1) * w + static_cast<size_t>(c)]
                                                 : s.values[k * w + static_cast<size_t>(c)];
}

// The sampler at `time`: `width` numbers; `rotation` slerps (LINEAR) and normalises.
std::vector<double> sample(const Sampler& s, double time, bool rotation) {
  const size_t n = s.times.size(), w = static_cast<size_t>(s.width);
  std::vector<double> out(w);
  const size_t after = static_cast<size_t>(std::upper_bound(s.times.begin(), s.times.end(), time) - s.times.begin());
  if (after == 0 || after == n || s.interpolation == Interpolation::Step) {
    const size_t k = after == 0 ? 0 : after - 1;
    for (size_t c = 0; c < w; ++c) out[c] = value(s, k, static_cast<int>(c));
    return out;
  }
  const size_t k = after - 1;
  const double d = static_cast<double>(s.times[k + 1]) - s.times[k], u = d > 0.0 ? (time - s.times[k]) / d : 1.0;
  if (s.interpolation == Interpolation::Linear && rotation) {
    const glm::dquat a(value(s, k, 3), value(s, k, 0), value(s, k, 1), value(s, k, 2));
    const glm::dquat b(value(s, k + 1, 3), value(s, k + 1, 0), value(s, k + 1, 1), value(s, k + 1, 2));
    const glm::dquat q = glm::slerp(glm::normalize(a), glm::normalize(b), u);  // the shorter arc
    return {q.x, q.y, q.z, q.w};
  }
  for (size_t c = 0; c < w; ++c) {
    const double v0 = value(s, k, static_cast<int>(c)), v1 = value(s, k + 1, static_cast<int>(c));
    if (s.interpolation == Interpolation::Linear) {
      out[c] = v0 + u * (v1 - v0);
      continue;
    }
    const double b0 = s.values[(3 * k + 2) * w + c], a1 = s.values[(3 * (k + 1)) * w + c];
    const double u2 = u * u, u3 = u2 * u;
    out[c] = (2 * u3 - 3 * u2 + 1) * v0 + d * (u3 - 2 * u2 + u) * b0 + (-2 * u3 + 3 * u2) * v1 + d * (u3 - u2) * a1;
  }
  if (rotation) {
    const double len = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
    if (len > 0.0)
      for (double& c : out) c /= len;
  }
  return out;
}

// The indices of the animations `select` names: all, an index, or a name.
std::vector<size_t> selected(const GltfContext& ctx, const std::string& select) {
  const auto& animations = ctx.model.animations;
  std::vector<size_t> out;
  if (select.empty()) {
    for (size_t i = 0; i < animations.size(); ++i) out.push_back(i);
    return out;
  }
  for (size_t i = 0; i < animations.size(); ++i)
    if (animations[i].name == select) return {i};
  char* end = nullptr;
  const long index = std::strtol(select.c_str(), &end, 10);
  if (*end == '\0' && index >= 0 && static_cast<size_t>(index) < animations.size()) return {static_cast<size_t>(index)};
  std::string names;
  for (size_t i = 0; i < animations.size(); ++i)
    names += fmt::format("{}{} \"{}\"", i ? ", " : "", i, animations[i].name);
  failGltf(ctx, fmt::format("--animation {}: no such animation (the file has {}{})", select, animations.size(),
                            animations.empty() ? "" : ": " + names));
}

// Morph targets of node n's mesh (every primitive has as many); 0 without a mesh.
int targetCount(const GltfContext& ctx, const tinygltf::Node& n) {
  if (n.mesh < 0 || static_cast<size_t>(n.mesh) >= ctx.model.meshes.size()) return 0;
  const auto& primitives = ctx.model.meshes[static_cast<size_t>(n.mesh)].primitives;
  return primitives.empty() ? 0 : static_cast<int>(primitives.front().targets.size());
}

void applyChannel(const GltfContext& ctx, const tinygltf::Animation& animation, size_t a, size_t c, double time,
                  std::vector<NodePose>& poses) {
  const tinygltf::AnimationChannel& ch = animation.channels[c];
  const std::string what = fmt::format("animation {} channel {}", a, c);
  const std::string& path = ch.target_path;
  if (path != "translation" && path != "rotation" && path != "scale" && path != "weights") {
    emitWarning(ctx.options, fmt::format("{}: {}: target path '{}' is not supported; skipped", ctx.file, what, path));
    return;
  }
  if (ch.target_node < 0 || static_cast<size_t>(ch.target_node) >= ctx.model.nodes.size())
    failGltf(ctx, fmt::format("{}: target node {} does not exist", what, ch.target_node));
  if (ch.sampler < 0 || static_cast<size_t>(ch.sampler) >= animation.samplers.size())
    failGltf(ctx, fmt::format("{}: sampler {} does not exist", what, ch.sampler));
  const tinygltf::Node& node = ctx.model.nodes[static_cast<size_t>(ch.target_node)];
  if (!node.matrix.empty() && path != "weights")
    failGltf(ctx,
             fmt::format("{}: node {} has a matrix; an animated node must use TRS (sec. 3.11)", what, ch.target_node));
  const int width = path == "rotation" ? 4 : path == "weights" ? targetCount(ctx, node) : 3;
  if (width == 0) failGltf(ctx, fmt::format("{}: node {} has no morph targets to weight", what, ch.target_node));
  const Sampler s = readSampler(ctx, what, animation.samplers[static_cast<size_t>(ch.sampler)], path, width);
  const std::vector<double> v = sample(s, time, path == "rotation");
  NodePose& pose = poses[static_cast<size_t>(ch.target_node)];
  if (path == "translation") pose.translation = glm::dvec3(v[0], v[1], v[2]);
  if (path == "scale") pose.scale = glm::dvec3(v[0], v[1], v[2]);
  if (path == "rotation") pose.rotation = glm::dquat(v[3], v[0], v[1], v[2]);
  if (path == "weights") pose.weights = v;
}

}  // namespace

std::vector<NodePose> evaluateAnimations(const GltfContext& ctx) {
  std::vector<NodePose> poses(ctx.model.nodes.size());
  if (!ctx.options.time) return poses;
  const double time = *ctx.options.time;
  if (!std::isfinite(time)) failGltf(ctx, fmt::format("--time {} is not finite", time));
  if (ctx.model.animations.empty()) {
    emitWarning(ctx.options, ctx.file + ": --time given but the file has no animations (its static pose is used)");
    return poses;
  }
  for (size_t a : selected(ctx, ctx.options.animation))
    for (size_t c = 0; c < ctx.model.animations[a].channels.size(); ++c)
      applyChannel(ctx, ctx.model.animations[a], a, c, time, poses);
  return poses;
}

}  // namespace penumbra::detail
