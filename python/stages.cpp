// The Python module's filtering stages on numpy arrays: each uploads its input into a buffer of the context (straight
// from the array's memory when it already is C-contiguous of the right type), runs the stage through the C++ API with
// the GIL released, and reads the result into a new array. Images are (height, width) or (height, width, channels).
// This file: moments and blur; tables.cpp: SAT, pyramids, Lloyd statistics.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <penumbra/penumbra.hpp>

#include "python/arrays.h"
#include "python/module.h"

namespace py = pybind11;

namespace penumbra::python {
namespace {

template <class T>
py::array_t<T> imageLike(const ImageShape& shape, bool planar = false) {
  if (shape.channels == 1 && !planar) return py::array_t<T>({shape.height, shape.width});
  return py::array_t<T>({shape.height, shape.width, shape.channels});
}

// Moments (or blurred moments) of a depth map, as float32 or, for half storage, numpy float16 (the same bits).
py::array runMoments(const Context& ctx, const Array<float>& depth, const MomentsConfig& config, bool blurred,
                     const BlurConfig& blur) {
  const ImageShape shape = shapeOf(depth, "moments");
  const bool half = config.storage == MomentStorage::Float16;
  const size_t channels = pn_moment_channels(static_cast<pn_moment_kind>(config.kind));
  const size_t planes = config.kind == MomentKind::Lvsm ? config.layers.size() : 1;
  const size_t texels = size_t(shape.width) * shape.height, bytes = planes * texels * channels * (half ? 2 : 4);
  std::vector<size_t> dims = {size_t(shape.height), size_t(shape.width), channels};
  if (config.kind == MomentKind::Lvsm) dims.insert(dims.begin(), planes);
  py::array out(py::dtype(half ? "float16" : "float32"), dims);
  const float* in = depth.data();
  void* result = out.mutable_data();
  py::gil_scoped_release release;
  DeviceBuffer source(ctx, texels * sizeof(float), in), target(ctx, bytes);
  cl_event done = nullptr;
  if (blurred)
    blurMoments(ctx, source.get(), shape.width, shape.height, config, blur, target.get(), {}, &done);
  else
    moments(ctx, source.get(), shape.width, shape.height, config, target.get(), {}, &done);
  download(ctx, target, done, result, bytes);
  return out;
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

py::array blurImage(const Context& ctx, const Array<float>& image, const std::string& filter, float sigma, int radius,
                    const std::string& method) {
  const BlurConfig config = blurConfig(filter, sigma, radius, method);
  const ImageShape shape = shapeOf(image, "blur");
  const size_t bytes = size_t(shape.width) * shape.height * shape.channels * sizeof(float);
  py::array_t<float> out = imageLike<float>(shape, image.ndim() == 3);
  const float* in = image.data();
  float* result = out.mutable_data();
  py::gil_scoped_release release;
  DeviceBuffer source(ctx, bytes, in), target(ctx, bytes);
  cl_event done = nullptr;
  blur(ctx, source.get(), target.get(), shape, config, {}, &done);
  download(ctx, target, done, result, bytes);
  return out;
}

}  // namespace

void bindStages(py::module_& m) {
  using namespace py::literals;
  m.def(
      "moments",
      [](const Context& ctx, const Array<float>& depth, const std::string& kind, float depthNear, float depthFar,
         float evsmPositive, float evsmNegative, const std::string& storage,
         const std::vector<std::pair<float, float>>& layers, float esmExponent) {
        const MomentsConfig config =
            momentsConfig(kind, depthNear, depthFar, evsmPositive, evsmNegative, esmExponent, storage, layers);
        return runMoments(ctx, depth, config, false, {});
      },
      "context"_a, "depth"_a, "kind"_a = "vsm", "depth_near"_a = 0.0f, "depth_far"_a = 1.0f, "evsm_positive"_a = 40.0f,
      "evsm_negative"_a = 5.0f, "storage"_a = "float32", "layers"_a = std::vector<std::pair<float, float>>{},
      "esm_exponent"_a = 80.0f,
      "Moments of a (height, width) depth map: (height, width, channels), LVSM (layers, height, width, 2); float16 "
      "storage returns the half bits as numpy float16. esm: e^(c (z - 1)) for esm_exponent c in [1, 80], else z.");
  m.def(
      "blur_moments",
      [](const Context& ctx, const Array<float>& depth, const std::string& kind, float depthNear, float depthFar,
         const std::string& storage, const std::string& filter, float sigma, int radius, const std::string& method,
         float esmExponent) {
        const MomentsConfig config = momentsConfig(kind, depthNear, depthFar, 40.0f, 5.0f, esmExponent, storage, {});
        const BlurConfig blur = blurConfig(filter, sigma, radius, method);
        return runMoments(ctx, depth, config, true, blur);
      },
      "context"_a, "depth"_a, "kind"_a = "vsm", "depth_near"_a = 0.0f, "depth_far"_a = 1.0f, "storage"_a = "float32",
      "filter"_a = "gaussian", "sigma"_a = 1.0f, "radius"_a = 1, "method"_a = "auto", "esm_exponent"_a = 80.0f,
      "The moments of a depth map blurred in one stage (equal to moments then blur; esm outside exponents [1, 80]: "
      "blurred in log space).");
  m.def("blur", &blurImage, "context"_a, "image"_a, "filter"_a = "gaussian", "sigma"_a = 1.0f, "radius"_a = 1,
        "method"_a = "auto", "Separable Gaussian or box blur with clamp-to-edge; the same shape back.");
}

}  // namespace penumbra::python
