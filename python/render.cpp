// The Python module's techniques, renderer and frames: render() releases the GIL, and a frame's channels are numpy
// arrays over the frame's own memory (zero-copy, read-only; each keeps the frame alive).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <map>
#include <penumbra/penumbra.hpp>
#include <string>

#include "python/arrays.h"
#include "python/module.h"

namespace py = pybind11;

namespace penumbra::python {
namespace {

// `value` as the text pn_params_set takes: str as is, bool as 0/1, numbers with 17 digits.
std::string paramText(const py::handle& value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "1" : "0";
  if (py::isinstance<py::int_>(value)) return std::to_string(value.cast<long long>());
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", value.cast<double>());
  return text;
}

}  // namespace

Params makeParams(const std::string& technique, const py::dict& values) {
  Params params(technique);
  for (const auto& [name, value] : values) params.set(name.cast<std::string>(), paramText(value));
  return params;
}

namespace {

// A read-only numpy view of one channel, owned by `frame` (the Python object, kept alive as the array's base).
py::array channelArray(const py::object& frame, const std::string& name) {
  const Frame& f = frame.cast<const Frame&>();
  const float* data = f.channel(name);
  py::array_t<float> array({f.height(), f.width()}, data, frame);
  py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return array;
}

py::list techniqueParams(const std::string& technique) {
  py::list out;
  for (size_t i = 0; i < pn_technique_param_count(technique.c_str()); ++i) {
    pn_param_info info;
    detail::check(pn_technique_param(technique.c_str(), i, &info));
    py::dict d;
    d["name"] = info.name, d["help"] = info.help, d["default"] = info.default_value;
    d["min"] = info.min, d["max"] = info.max, d["choices"] = std::string(info.choices);
    d["text"] = info.is_text != 0, d["text_default"] = info.text_default;
    out.append(d);
  }
  if (pn_technique_param_count(technique.c_str()) == 0) Params check(technique);  // an unknown name raises
  return out;
}

// One light of a frame: a Light, or a (Light, technique, params) tuple with its own technique.
FrameLight frameLight(const py::handle& item) {
  if (py::isinstance<Light>(item)) return {item.cast<Light>(), std::nullopt};
  const py::tuple t = item.cast<py::tuple>();
  if (t.size() != 3) throw py::value_error("a frame light is a Light or a (Light, technique, params) tuple");
  return {t[0].cast<Light>(), makeParams(t[1].cast<std::string>(), t[2].cast<py::dict>())};
}

// render()'s `outputs`: None, every output; else the names of those kept (pn_frame_output_bits).
unsigned outputBits(const std::optional<std::vector<std::string>>& outputs) {
  if (!outputs) return PN_FRAME_OUTPUTS_ALL;
  static const std::map<std::string, unsigned> kBits = {{"preview", PN_FRAME_OUTPUT_PREVIEW_BIT},
                                                        {"surfaces", PN_FRAME_OUTPUT_SURFACES_BIT},
                                                        {"debug", PN_FRAME_OUTPUT_DEBUG_BIT}};
  unsigned bits = 0;
  for (const std::string& name : *outputs) {
    auto it = kBits.find(name);
    if (it == kBits.end()) throw py::value_error("render: output \"" + name + "\" is none of preview, surfaces, debug");
    bits |= it->second;
  }
  return bits;
}

Frame render(Renderer& renderer, const std::string& technique, const py::dict& params,
             const std::optional<Camera>& camera, const std::optional<py::list>& lights, const std::string& channels,
             const std::optional<std::vector<std::string>>& outputs) {
  if (channels != "all" && channels != "on_request")
    throw py::value_error("render: channels '" + channels + "' is not all or on_request");
  const unsigned bits = outputBits(outputs);
  const Params fallback = makeParams(technique, params);
  std::vector<FrameLight> frameLights;
  if (lights)
    for (const py::handle& item : *lights) frameLights.push_back(frameLight(item));
  py::gil_scoped_release release;  // no Python object is touched from here on
  if (channels == "all" && bits == PN_FRAME_OUTPUTS_ALL) return renderer.render(camera, frameLights, &fallback);
  RenderOptions options;
  options.channels = channels == "all" ? FrameChannels::All : FrameChannels::OnRequest;
  options.outputs = bits;
  return renderer.enqueue(camera, frameLights, &fallback, options);
}

pn_frame_output frameOutput(const std::string& output, const char* function) {
  static const std::map<std::string, pn_frame_output> kOutputs = {{"preview", PN_FRAME_PREVIEW},
                                                                  {"position", PN_FRAME_POSITION},
                                                                  {"normal", PN_FRAME_NORMAL},
                                                                  {"depth", PN_FRAME_DEPTH}};
  auto it = kOutputs.find(output);
  if (it == kOutputs.end())
    throw py::value_error(std::string(function) + ": \"" + output + "\" is none of preview, position, normal, depth");
  return it->second;
}

// A pyopencl array over a frame's cl_mem (retained by pyopencl, so it outlives the frame), on `queue`, whose context
// must be the buffer's.
py::object deviceArray(cl_mem mem, const py::object& queue, std::vector<py::ssize_t> dims) {
  cl_context owner = nullptr;
  clGetMemObjectInfo(mem, CL_MEM_CONTEXT, sizeof(owner), &owner, nullptr);
  if (clHandle(queue.attr("context"), "queue") != reinterpret_cast<uintptr_t>(owner))
    throw py::value_error("the queue's context is not the frame's (penumbra.Context.from_queue renders on its queue)");
  const py::module_ cl = py::module_::import("pyopencl");
  const py::object buffer = cl.attr("Buffer").attr("from_int_ptr")(reinterpret_cast<uintptr_t>(mem), true);
  return py::module_::import("pyopencl.array")
      .attr("Array")(queue, py::cast(dims), py::dtype("float32"), py::arg("data") = buffer);
}

}  // namespace

void bindRender(py::module_& m) {
  m.def("techniques", &techniques, "The techniques' names, in the CLI's order.");
  m.def("technique_params", &techniqueParams, py::arg("technique"),
        "The technique's parameters: dicts of name, help, default, min, max, choices, text, text_default.");

  py::class_<Frame>(m, "Frame", "A rendered frame: channels as numpy arrays (height x width, top row first).")
      .def_property_readonly("width", &Frame::width)
      .def_property_readonly("height", &Frame::height)
      .def_property_readonly("channel_names", &Frame::channelNames)
      .def_property_readonly("light_layers", &Frame::lightLayers)
      .def("__getitem__", &channelArray, py::arg("name"), "The channel: a read-only float32 view of the frame.")
      .def("__contains__",
           [](const Frame& f, const std::string& name) {
             const std::vector<std::string> names = f.channelNames();
             return std::find(names.begin(), names.end(), name) != names.end();
           })
      .def("attribute", &Frame::attribute, py::arg("name"), "A provenance attribute, or None.")
      .def_property_readonly("passes",
                             [](const Frame& f) {
                               std::vector<std::pair<std::string, double>> out;
                               for (const PassTime& p : f.passes()) out.emplace_back(p.name, p.ms);
                               return out;
                             })
      .def(
          "visibility_buffer",
          [](const Frame& f, size_t light) { return reinterpret_cast<uintptr_t>(f.visibilityBuffer(light)); },
          py::arg("light") = 0,
          "The light's visibility cl_mem (an integer handle, rows bottom-up), owned by the frame.")
      .def(
          "device_buffer",
          [](const Frame& f, const std::string& output) {
            return reinterpret_cast<uintptr_t>(f.deviceBuffer(frameOutput(output, "device_buffer")));
          },
          py::arg("output"),
          "The preview (float4 RGBA), position, normal (float4) or depth (float) cl_mem as an integer handle, rows "
          "bottom-up, owned by the frame.")
      .def(
          "visibility_array",
          [](const Frame& f, const py::object& queue, size_t light) {
            return deviceArray(f.visibilityBuffer(light), queue, {f.height(), f.width()});
          },
          py::arg("queue"), py::arg("light") = 0,
          "The light's visibility as a (height, width) float32 pyopencl array on `queue` (rows bottom-up), in place: "
          "the frame's own buffer, kept alive by the array.")
      .def(
          "device_array",
          [](const Frame& f, const std::string& output, const py::object& queue) {
            const pn_frame_output which = frameOutput(output, "device_array");
            std::vector<py::ssize_t> dims = {f.height(), f.width()};
            if (which != PN_FRAME_DEPTH) dims.push_back(4);
            return deviceArray(f.deviceBuffer(which), queue, dims);
          },
          py::arg("output"), py::arg("queue"),
          "The preview, position, normal ((height, width, 4) float32) or depth ((height, width)) as a pyopencl array "
          "on `queue` (rows bottom-up), in place: the frame's own buffer, kept alive by the array.")
      .def("save_exr", &Frame::saveExr, py::arg("path"));

  py::class_<Renderer>(m, "Renderer", "Draws frames of one scene on one context.")
      .def(py::init<const Context&, const Scene&>(), py::arg("context"), py::arg("scene"))
      .def("render", &render, py::arg("technique") = "pcss", py::arg("params") = py::dict(),
           py::arg("camera") = std::nullopt, py::arg("lights") = std::nullopt, py::arg("channels") = "all",
           py::arg("outputs") = std::nullopt,
           "Renders a frame, releasing the GIL. No camera: the scene's default; no lights: the scene's (else the "
           "framing light). Lights: Light objects (shadowed by technique/params) or (Light, technique, params) "
           "tuples. channels: 'all' (every channel downloaded before it returns) or 'on_request' (nothing waited "
           "for: each channel read from the device when first indexed; no debug channels). outputs: None (all), or "
           "those of 'preview', 'surfaces' (position, normal, depth), 'debug' the frame keeps besides each light's "
           "visibility ([] : the visibility alone, no preview pass).");
}

}  // namespace penumbra::python
