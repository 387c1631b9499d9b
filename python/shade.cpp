// The Python module's penumbra.Shader: a technique on the caller's own light map and G-buffer (penumbra/shade.h) from
// numpy or pyopencl arrays (python/arrays.h): pyopencl arrays are used in place and chained by events, numpy arrays
// uploaded; the visibility comes back as the G-buffer's kind of array (or into `out`). Matrices are 4x4 arrays indexed
// [row, column] as numpy writes them, for column vectors (glm's and OpenGL's convention, transposed in memory).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <map>
#include <optional>
#include <penumbra/penumbra.hpp>
#include <string>
#include <vector>

#include "python/arrays.h"
#include "python/module.h"

namespace py = pybind11;

namespace penumbra::python {

namespace {

constexpr char kShade[] = "Shader.shade";

// A 4x4 matrix given [row, column] into the C API's column-major floats.
void matrix(const py::object& m, float out[16], const char* name) {
  const Array<float> a = contiguous(m, "float32");
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    throw py::value_error(std::string(kShade) + ": " + name + " is not a 4x4 matrix");
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) out[col * 4 + row] = a.at(row, col);
}

template <class Enum>
Enum choice(const std::string& value, const std::map<std::string, Enum>& choices, const char* name) {
  const auto it = choices.find(value);
  if (it != choices.end()) return it->second;
  std::string known;
  for (const auto& [key, unused] : choices) known += (known.empty() ? "" : ", ") + key;
  throw py::value_error(std::string(kShade) + ": " + name + " '" + value + "' is not one of " + known);
}

const std::map<std::string, pn_ndc_depth> kNdc = {{"minus_one_to_one", PN_NDC_DEPTH_MINUS_ONE_TO_ONE},
                                                  {"zero_to_one", PN_NDC_DEPTH_ZERO_TO_ONE}};

// (rows, cols[, channels]) of an input, checked.
void requireShape(const ArrayIn& in, py::ssize_t rows, py::ssize_t cols, py::ssize_t channels, const char* name) {
  std::vector<py::ssize_t> want = {rows, cols};
  if (channels > 1) want.push_back(channels);
  if (in.shape() != want)
    throw py::value_error(std::string(kShade) + ": " + name + " has the shape " +
                          py::repr(py::cast(in.shape())).cast<std::string>() + ", not " +
                          py::repr(py::cast(want)).cast<std::string>());
}

pn_device_image image(const ArrayIn& in, bool topDown) { return {in.mem(), 0, 0, topDown ? 1 : 0}; }

// penumbra.Shader: a Shader and the context its arrays are uploaded to.
struct PyShader {
  Context ctx;
  Shader shader;
  explicit PyShader(const Context& context) : ctx(context), shader(context) {}
};

py::object shade(const PyShader& self, const std::string& technique, const py::dict& params, const py::object& lightMap,
                 const py::object& lightView, const py::object& lightProjection, const std::string& lightType,
                 float lightRadius, float lightAngularRadiusDeg, const std::string& depthStorage,
                 const std::string& lightNdc, float depthNear, float depthFar, const py::object& positions,
                 const py::object& depth, const py::object& inverseViewProjection, const std::string& cameraNdc,
                 float clearDepth, const py::object& normals,
                 const std::optional<std::pair<std::array<float, 3>, std::array<float, 3>>>& sceneBounds, bool topDown,
                 const py::object& out) {
  const Context& ctx = self.ctx;
  const Params p = makeParams(technique, params);
  ShadeDesc d;
  d.light_type =
      choice<pn_light_type>(lightType, {{"spot", PN_LIGHT_SPOT}, {"directional", PN_LIGHT_DIRECTIONAL}}, "light_type");
  d.light_radius = lightRadius, d.light_angular_radius_deg = lightAngularRadiusDeg;
  d.light_depth_storage = choice<pn_depth_storage>(
      depthStorage, {{"window", PN_DEPTH_WINDOW}, {"linear", PN_DEPTH_LINEAR}}, "depth_storage");
  d.light_ndc_depth = choice(lightNdc, kNdc, "light_ndc");
  d.camera_ndc_depth = choice(cameraNdc, kNdc, "camera_ndc");
  matrix(lightView, d.light_view, "light_view");
  matrix(lightProjection, d.light_projection, "light_projection");
  d.light_depth_near = depthNear, d.light_depth_far = depthFar;
  d.camera_clear_depth = clearDepth;
  if (positions.is_none() == depth.is_none())
    throw py::value_error(std::string(kShade) + ": give positions or depth (with inverse_view_projection), not both");

  const ArrayIn map(ctx, lightMap, "float32", kShade, "light_map");
  if (map.shape().size() != 2) throw py::value_error(std::string(kShade) + ": light_map is not (size, size)");
  requireShape(map, map.shape()[0], map.shape()[0], 1, "light_map");
  d.light_map_size = static_cast<uint32_t>(map.shape()[0]);
  d.light_depth = image(map, topDown);
  const bool byDepth = !depth.is_none();
  const ArrayIn gbuffer(ctx, byDepth ? depth : positions, "float32", kShade, byDepth ? "depth" : "positions");
  if (gbuffer.shape().size() < 2) throw py::value_error(std::string(kShade) + ": the G-buffer is not an image");
  const py::ssize_t height = gbuffer.shape()[0], width = gbuffer.shape()[1];
  requireShape(gbuffer, height, width, byDepth ? 1 : 4, byDepth ? "depth" : "positions");
  d.width = static_cast<uint32_t>(width), d.height = static_cast<uint32_t>(height);
  (byDepth ? d.depth : d.positions) = image(gbuffer, topDown);
  if (byDepth) {
    if (inverseViewProjection.is_none())
      throw py::value_error(std::string(kShade) + ": depth needs inverse_view_projection");
    matrix(inverseViewProjection, d.camera_inverse_view_projection, "inverse_view_projection");
  }
  std::optional<ArrayIn> normalArray;
  if (!normals.is_none()) {
    normalArray.emplace(ctx, normals, "float32", kShade, "normals");
    requireShape(*normalArray, height, width, 4, "normals");
    d.normals = image(*normalArray, topDown);
  }
  if (sceneBounds) {
    d.has_scene_bounds = 1;
    for (int i = 0; i < 3; ++i) d.scene_min[i] = sceneBounds->first[i], d.scene_max[i] = sceneBounds->second[i];
  }
  ArrayOut result(ctx, gbuffer, {height, width}, "float32", out, kShade);
  d.visibility = {result.mem(), 0, 0, topDown ? 1 : 0};
  std::vector<cl_event> waits = result.waits(gbuffer);
  for (const ArrayIn* in : std::array<const ArrayIn*, 2>{&map, normalArray ? &*normalArray : nullptr})
    if (in != nullptr) waits.insert(waits.end(), in->waits().begin(), in->waits().end());
  const StageEvent done([&](cl_event* event) { self.shader.shade(p, d, waits, event); });
  return result.finish(done.get());
}

}  // namespace

void bindShade(py::module_& m) {
  using namespace py::literals;
  py::class_<PyShader>(
      m, "Shader",
      "Shades techniques from the caller's own light depth map and camera G-buffer on one context, "
      "keeping a technique's buffers across calls while its parameters and the map size stay the same.")
      .def(py::init<const Context&>(), "context"_a)
      .def("shade", &shade, "technique"_a, "params"_a = py::dict(), py::kw_only(), "light_map"_a, "light_view"_a,
           "light_projection"_a, "light_type"_a = "spot", "light_radius"_a = 0.0f, "light_angular_radius_deg"_a = 0.0f,
           "depth_storage"_a = "window", "light_ndc"_a = "minus_one_to_one", "depth_near"_a = 0.0f,
           "depth_far"_a = 0.0f, "positions"_a = py::none(), "depth"_a = py::none(),
           "inverse_view_projection"_a = py::none(), "camera_ndc"_a = "minus_one_to_one", "clear_depth"_a = 1.0f,
           "normals"_a = py::none(), "scene_bounds"_a = py::none(), "top_down"_a = false, "out"_a = py::none(),
           "Visibility (height, width) of the light whose (size, size) depth map is light_map (light_view and "
           "light_projection: 4x4, [row, column], column vectors; depth_storage window or linear; light_ndc "
           "minus_one_to_one or zero_to_one) at the G-buffer's pixels: positions (height, width, 4), w = 0 for "
           "background, or depth (height, width) with inverse_view_projection, camera_ndc and clear_depth; normals "
           "(height, width, 4) optional. scene_bounds: ((min x, y, z), (max x, y, z)). top_down: every image's first "
           "row is its top row. pyopencl arrays are used in place and the result is a pyopencl array carrying the "
           "call's event (or out=, a pyopencl array or Buffer); numpy arrays give a numpy array. penumbra/shade.h "
           "documents each input.")
      .def(
          "attribute", [](const PyShader& self, const std::string& name) { return self.shader.attribute(name); },
          "name"_a,
          "What the last successful shade() recorded ('penumbra:light-fit', 'penumbra:pcf-radius', ...), or None.");
  m.def(
      "takes_caller_map",
      [](const std::string& technique) {
        std::string reason;
        const bool takes = takesCallerMap(technique, &reason);
        return py::make_tuple(takes, reason);
      },
      "technique"_a,
      "(True, '') when the technique shades from a caller's map (Shader.shade), else (False, why it cannot).");
}

}  // namespace penumbra::python
