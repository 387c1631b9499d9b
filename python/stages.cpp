// The Python module's filtering stages on numpy or pyopencl arrays (python/arrays.h): numpy inputs are uploaded into a
// buffer of the context (straight from the array's memory when it already is C-contiguous of the right type) and the
// result read into a new numpy array; pyopencl arrays are used in place and the result is a new pyopencl array on the
// input's queue, chained by events. The stage runs through the C++ API with the GIL released. Images are (height,
// width) or (height, width, channels). This file: moments and blur; tables.cpp: SAT, pyramids, Lloyd statistics.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <penumbra/penumbra.hpp>

#include "python/arrays.h"
#include "python/module.h"

namespace py = pybind11;

namespace penumbra::python {
namespace {

// Moments (or blurred moments) of a depth map, as float32 or, for half storage, float16 (the same bits).
py::object runMoments(const Context& ctx, const py::object& depth, const MomentsConfig& config, bool blurred,
                      const BlurConfig& blur, const py::object& into) {
  const char* stage = blurred ? "blur_moments" : "moments";
  const ArrayIn in(ctx, depth, "float32", stage, "depth");
  const ImageShape shape = shapeOf(in.shape(), stage);
  const bool half = config.storage == MomentStorage::Float16;
  const py::ssize_t channels = pn_moment_channels(static_cast<pn_moment_kind>(config.kind));
  std::vector<py::ssize_t> dims = {shape.height, shape.width, channels};
  if (config.kind == MomentKind::Lvsm) dims.insert(dims.begin(), py::ssize_t(config.layers.size()));
  ArrayOut out(ctx, in, dims, half ? "float16" : "float32", into, stage);
  const std::vector<cl_event> waits = out.waits(in);
  const StageEvent done([&](cl_event* event) {
    if (blurred)
      blurMoments(ctx, in.mem(), shape.width, shape.height, config, blur, out.mem(), waits, event);
    else
      moments(ctx, in.mem(), shape.width, shape.height, config, out.mem(), waits, event);
  });
  return out.finish(done.get());
}

MomentsConfig momentsConfig(const std::string& kind, float depthNear, float depthFar, float evsmPositive,
                            float evsmNegative, float esmExponent, const std::string& storage,
                            const std::vector<std::pair<float, float>>& layers) {
  static const std::map<std::string, MomentKind> kKinds = {{"vsm", MomentKind::Vsm},     {"evsm2", MomentKind::Evsm2},
                                                           {"evsm4", MomentKind::Evsm4}, {"lvsm", MomentKind::Lvsm},
                                                           {"msm", MomentKind::Msm},     {"esm", MomentKind::Esm}};
  auto it = kKinds.find(kind);
  if (it == kKinds.end())
    throw py::value_error("moments: kind '" + kind + "' is not vsm, evsm2, evsm4, lvsm, msm or esm");
  if (storage != "float32" && storage != "float16")
    throw py::value_error("moments: storage '" + storage + "' is not float32 or float16");
  MomentsConfig config;
  config.kind = it->second;
  config.depthNear = depthNear, config.depthFar = depthFar;
  config.evsmPositive = evsmPositive, config.evsmNegative = evsmNegative;
  config.esmExponent = esmExponent;
  config.storage = storage == "float16" ? MomentStorage::Float16 : MomentStorage::Float32;
  for (const auto& [p, q] : layers) config.layers.push_back({p, q});
  return config;
}

BlurConfig blurConfig(const std::string& filter, float sigma, int radius, const std::string& method) {
  BlurConfig config;
  if (filter != "gaussian" && filter != "box")
    throw py::value_error("blur: filter '" + filter + "' is not gaussian or box");
  config.filter = filter == "box" ? BlurFilter::Box : BlurFilter::Gaussian;
  config.sigma = sigma, config.radius = radius;
  if (method == "auto")
    config.method = BlurMethod::Auto;
  else if (method == "direct")
    config.method = BlurMethod::Direct;
  else if (method == "running_sums")
    config.method = BlurMethod::RunningSums;
  else
    throw py::value_error("blur: method '" + method + "' is not auto, direct or running_sums");
  return config;
}

py::object blurImage(const Context& ctx, const py::object& image, const std::string& filter, float sigma, int radius,
                     const std::string& method, const py::object& into) {
  const BlurConfig config = blurConfig(filter, sigma, radius, method);
  const ArrayIn in(ctx, image, "float32", "blur", "image");
  const ImageShape shape = shapeOf(in.shape(), "blur");
  ArrayOut out(ctx, in, in.shape(), "float32", into, "blur");
  const std::vector<cl_event> waits = out.waits(in);
  const StageEvent done([&](cl_event* event) { blur(ctx, in.mem(), out.mem(), shape, config, waits, event); });
  return out.finish(done.get());
}

}  // namespace

void bindStages(py::module_& m) {
  using namespace py::literals;
  m.def(
      "moments",
      [](const Context& ctx, const py::object& depth, const std::string& kind, float depthNear, float depthFar,
         float evsmPositive, float evsmNegative, const std::string& storage,
         const std::vector<std::pair<float, float>>& layers, float esmExponent, const py::object& out) {
        const MomentsConfig config =
            momentsConfig(kind, depthNear, depthFar, evsmPositive, evsmNegative, esmExponent, storage, layers);
        return runMoments(ctx, depth, config, false, {}, out);
      },
      "context"_a, "depth"_a, "kind"_a = "vsm", "depth_near"_a = 0.0f, "depth_far"_a = 1.0f, "evsm_positive"_a = 40.0f,
      "evsm_negative"_a = 5.0f, "storage"_a = "float32", "layers"_a = std::vector<std::pair<float, float>>{},
      "esm_exponent"_a = 80.0f, "out"_a = py::none(),
      "Moments of a (height, width) depth map: (height, width, channels), LVSM (layers, height, width, 2); float16 "
      "storage returns the half bits as numpy float16. esm: e^(c (z - 1)) for esm_exponent c in [1, 80], else z. out: "
      "a pyopencl array or Buffer to write instead of a new array.");
  m.def(
      "blur_moments",
      [](const Context& ctx, const py::object& depth, const std::string& kind, float depthNear, float depthFar,
         const std::string& storage, const std::string& filter, float sigma, int radius, const std::string& method,
         float esmExponent, const py::object& out) {
        const MomentsConfig config = momentsConfig(kind, depthNear, depthFar, 40.0f, 5.0f, esmExponent, storage, {});
        const BlurConfig blur = blurConfig(filter, sigma, radius, method);
        return runMoments(ctx, depth, config, true, blur, out);
      },
      "context"_a, "depth"_a, "kind"_a = "vsm", "depth_near"_a = 0.0f, "depth_far"_a = 1.0f, "storage"_a = "float32",
      "filter"_a = "gaussian", "sigma"_a = 1.0f, "radius"_a = 1, "method"_a = "auto", "esm_exponent"_a = 80.0f,
      "out"_a = py::none(),
      "The moments of a depth map blurred in one stage (equal to moments then blur; esm outside exponents [1, 80]: "
      "blurred in log space).");
  m.def("blur", &blurImage, "context"_a, "image"_a, "filter"_a = "gaussian", "sigma"_a = 1.0f, "radius"_a = 1,
        "method"_a = "auto", "out"_a = py::none(),
        "Separable Gaussian or box blur with clamp-to-edge; the same shape back (into `out`, a pyopencl array or "
        "Buffer, when given).");
}

}  // namespace penumbra::python
