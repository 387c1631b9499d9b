// The `penumbra` Python module: the C++ API's names in Python (OpenImageIO's and Mitsuba's habit), numpy arrays for
// images. penumbra::Error becomes ValueError (bad arguments), MemoryError, or penumbra.Error's subclasses, with the
// library's message; here also the version, contexts, cameras, lights and scenes.
#include "python/module.h"

#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <penumbra/penumbra.hpp>
#include <string>

#include "python/arrays.h"

namespace py = pybind11;

namespace penumbra::python {
namespace {

// penumbra.Error and one subclass per status that is not a built-in Python error; `code` holds the OpenCL error.
struct Errors {
  py::object base, opencl, build, noDevice, scene;
};

void translate(const Errors& errors, const Error& e) {
  py::object type;
  switch (e.status()) {
    case PN_ERROR_INVALID_ARGUMENT:
      PyErr_SetString(PyExc_ValueError, e.what());
      return;
    case PN_ERROR_OUT_OF_MEMORY:
      PyErr_SetString(PyExc_MemoryError, e.what());
      return;
    case PN_ERROR_OPENCL:
      type = errors.opencl;
      break;
    case PN_ERROR_BUILD:
      type = errors.build;
      break;
    case PN_ERROR_NO_DEVICE:
      type = errors.noDevice;
      break;
    case PN_ERROR_SCENE:
      type = errors.scene;
      break;
    default:
      type = errors.base;
      break;
  }
  py::object instance = type(e.what());
  instance.attr("code") = e.clError();
  PyErr_SetObject(type.ptr(), instance.ptr());
}

void bindErrors(py::module_& m) {
  static Errors errors;  // the module's own types, alive as long as the module
  py::object runtime = py::reinterpret_borrow<py::object>(PyExc_RuntimeError);
  auto make = [&](const char* name, py::object base, const char* doc) {
    py::object type = py::reinterpret_steal<py::object>(
        PyErr_NewExceptionWithDoc((std::string("penumbra.") + name).c_str(), doc, base.ptr(), nullptr));
    m.attr(name) = type;
    return type;
  };
  errors.base =
      make("Error", runtime,
           "A failure of penumbra's (bad arguments raise ValueError, exhausted memory MemoryError); `code` is "
           "the OpenCL error code where OpenCL reported one, else 0.");
  errors.opencl = make("OpenCLError", errors.base,
                       "An OpenCL call failed: the message names the error (CL_INVALID_WORK_GROUP_SIZE, ...), the "
                       "kernel and the stage; `code` is its value.");
  errors.build =
      make("BuildError", errors.base, "A kernel did not compile for the device; the message has the build log.");
  errors.noDevice = make("NoDeviceError", errors.base,
                         "No OpenCL device matches the request (no platform, or none of the kind or name asked for).");
  errors.scene =
      make("SceneError", errors.base,
           "A scene could not be loaded: a malformed or unreadable glTF or scene file, out-of-range indices, "
           "non-finite vertices, an empty scene.");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      translate(errors, e);
    }
  });
}

template <class Struct>
void vec3(py::class_<Struct>& c, const char* name, std::array<float, 3> Struct::*member, const char* doc) {
  c.def_property(
      name, [member](const Struct& s) { return py::make_tuple((s.*member)[0], (s.*member)[1], (s.*member)[2]); },
      [member](Struct& s, const std::array<float, 3>& v) { s.*member = v; }, doc);
}

// A Context on the caller's objects, each an integer handle or a pyopencl object; `function` names them in errors.
Context contextOn(const py::handle& context, const py::handle& device, const py::handle& queue, const char* function) {
  auto handle = [function](const py::handle& object, const char* name) {
    return clHandle(object, (std::string(function) + ": " + name).c_str());
  };
  return Context(reinterpret_cast<cl_context>(handle(context, "context")),
                 reinterpret_cast<cl_device_id>(handle(device, "device")),
                 reinterpret_cast<cl_command_queue>(handle(queue, "queue")));
}

void bindContext(py::module_& m) {
  py::class_<Context>(m, "Context", "An OpenCL device, context and in-order queue with penumbra's kernels.")
      .def(py::init([](const std::string& device, std::optional<std::string> cacheDir, uint64_t localMemLimit,
                       std::optional<std::string> layouts, std::optional<py::function> log) {
             ContextOptions options;
             options.device = device, options.cacheDir = std::move(cacheDir);
             options.localMemLimit = localMemLimit, options.layouts = std::move(layouts);
             if (log) {
               // Called from the library's threads with the GIL released; freed with the context, under the GIL.
               std::shared_ptr<py::function> held(new py::function(std::move(*log)), [](py::function* f) {
                 py::gil_scoped_acquire gil;
                 delete f;
               });
               options.log = [held](const std::string& message) {
                 py::gil_scoped_acquire gil;
                 (*held)(message);
               };
             }
             return Context(options);
           }),
           py::arg("device") = "", py::kw_only(), py::arg("cache_dir") = py::none(), py::arg("local_mem_limit") = 0,
           py::arg("layouts") = py::none(), py::arg("log") = py::none(),
           "Opens a device: '' for PENUMBRA_DEVICE, 'auto', 'cpu', 'gpu', a name substring or 'P:D'. cache_dir: a "
           "folder for compiled programs ('' none; None: PENUMBRA_CACHE_DIR); local_mem_limit: bytes of local memory "
           "the kernels plan with (0: the device's); layouts: 'gpu', 'nvidia' or '' (None: PENUMBRA_LAYOUTS); log: "
           "called with a message for each program built or loaded from the cache.")
      .def("prebuild", &Context::prebuild, py::arg("names"),
           "Builds now the programs of the named techniques ('pcss', ...) and stages ('moments', 'blur', 'sat', "
           "'pyramid', 'reduce'), or 'all', so that later calls do not (pn_context_prebuild).",
           py::call_guard<py::gil_scoped_release>())
      .def_static(
          "from_cl",
          [](const py::object& context, const py::object& device, const py::object& queue) {
            return contextOn(context, device, queue, "from_cl");
          },
          py::arg("context"), py::arg("device"), py::arg("queue"),
          "A context on the caller's OpenCL objects: pyopencl's Context, Device and CommandQueue, or integer handles "
          "(cl_context, cl_device_id, an in-order cl_command_queue): retained while it lives, never finished.")
      .def_static(
          "from_queue",
          [](const py::object& queue) {
            return contextOn(queue.attr("context"), queue.attr("device"), queue, "from_queue");
          },
          py::arg("queue"),
          "A context on a pyopencl.CommandQueue (in order) and its context and device: penumbra's commands go into "
          "that queue, after the caller's, and stages take and give pyopencl arrays on it in place.")
      .def_property_readonly("device_name", &Context::deviceName)
      .def_property_readonly("cl_context", [](const Context& c) { return reinterpret_cast<uintptr_t>(c.clContext()); })
      .def_property_readonly("cl_device", [](const Context& c) { return reinterpret_cast<uintptr_t>(c.clDevice()); })
      .def_property_readonly("cl_queue", [](const Context& c) { return reinterpret_cast<uintptr_t>(c.clQueue()); });
}

void bindCameraAndLight(py::module_& m) {
  py::class_<Camera> camera(m, "Camera", "A camera, Y up, looking from eye to target.");
  camera.def(py::init<>())
      .def_static("parse", &Camera::parse, py::arg("spec"), "'EX,EY,EZ:TX,TY,TZ[:FOVY_DEG]', the CLI's --camera.")
      .def_readwrite("orthographic", &Camera::orthographic)
      .def_readwrite("fov_y_deg", &Camera::fovYDeg)
      .def_readwrite("ortho_half_height", &Camera::orthoHalfHeight)
      .def_readwrite("clip_near", &Camera::clipNear)
      .def_readwrite("clip_far", &Camera::clipFar)
      .def_readwrite("width", &Camera::width)
      .def_readwrite("height", &Camera::height);
  vec3(camera, "eye", &Camera::eye, "Position.");
  vec3(camera, "target", &Camera::target, "The point it looks at.");
  vec3(camera, "up", &Camera::up, "Preferred up direction.");

  py::enum_<LightType>(m, "LightType", "What a Light is: SPOT (a cone with a disk), DIRECTIONAL (a sun) or POINT.")
      .value("SPOT", LightType::Spot)
      .value("DIRECTIONAL", LightType::Directional)
      .value("POINT", LightType::Point);
  py::class_<Light> light(m, "Light", "A spot, directional or point light.");
  light.def(py::init<>())
      .def_static("parse", &Light::parse, py::arg("spec"), "'spot:P:T:FOV[:R]', 'dir:D[:ANGLE]' or 'point:P[:R]'.")
      .def_readwrite("type", &Light::type)
      .def_readwrite("name", &Light::name)
      .def_readwrite("fov_deg", &Light::fovDeg)
      .def_readwrite("radius", &Light::radius)
      .def_readwrite("inner_fov_deg", &Light::innerFovDeg)
      .def_readwrite("range", &Light::range)
      .def_readwrite("angular_radius_deg", &Light::angularRadiusDeg);
  vec3(light, "position", &Light::position, "Spot and point: position.");
  vec3(light, "target", &Light::target, "Spot: the point it aims at.");
  vec3(light, "direction", &Light::direction, "Directional: the direction the light travels.");
}

}  // namespace

void bindScene(py::module_& m) {
  bindContext(m);
  bindCameraAndLight(m);
  py::class_<Scene> scene(m, "Scene", "A loaded scene: a .gltf/.glb model, a .json scene file or builtin:NAME.");
  scene
      .def(py::init([](const std::string& spec, std::optional<double> time, const std::string& animation) {
             return Scene(spec, LoadOptions{time, animation});
           }),
           py::arg("spec"), py::arg("time") = std::nullopt, py::arg("animation") = "")
      .def_property_readonly("triangle_count", &Scene::triangleCount)
      .def_property_readonly("cameras", &Scene::cameras)
      .def_property_readonly("lights", &Scene::lights)
      .def_property_readonly("bounds", &Scene::bounds)
      .def("default_camera", &Scene::defaultCamera, "The scene's first camera, else a framing view.")
      .def("framing_light", &Scene::framingLight, "The light a frame uses when the scene has none.");
  bindMeshes(scene);
}

}  // namespace penumbra::python

PYBIND11_MODULE(penumbra, m) {
  m.doc() = "penumbra: filtered and soft shadows for glTF scenes, every stage an OpenCL kernel";
  m.attr("__version__") = penumbra::version();
  penumbra::python::bindErrors(m);
  penumbra::python::bindScene(m);
  penumbra::python::bindRender(m);
  penumbra::python::bindStages(m);
  penumbra::python::bindTables(m);
  penumbra::python::bindShade(m);
}
