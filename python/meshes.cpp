// penumbra.Scene.from_meshes: a scene of the caller's own numpy triangle arrays (pn_scene_create). Each mesh is a
// dict: positions (N, 3) and indices (M, 3) required; normals (N, 3), transform (4, 4) (world = transform @ [x, y,
// z, 1], numpy's row-major matrix), name and double_sided optional. Arrays of other dtypes or layouts are converted.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include <penumbra/penumbra.hpp>

#include "python/arrays.h"
#include "python/module.h"

namespace py = pybind11;

namespace penumbra::python {
namespace {

// The arrays a pn_mesh points into, kept alive until pn_scene_create returns.
struct MeshArrays {
  Array<float> positions, normals, transform;
  Array<uint32_t> indices;
  std::string name;
};

Array<float> rows3(const py::handle& value, const std::string& what) {
  Array<float> array = Array<float>::ensure(value);
  if (!array || array.ndim() != 2 || array.shape(1) != 3)
    throw py::value_error("Scene.from_meshes: " + what + " must be an (N, 3) array");
  return array;
}

pn_mesh meshOf(const py::dict& spec, size_t index, MeshArrays& keep) {
  const std::string what = "meshes[" + std::to_string(index) + "]";
  for (const char* key : {"positions", "indices"})
    if (!spec.contains(key)) throw py::value_error("Scene.from_meshes: " + what + " has no \"" + key + "\"");
  keep.positions = rows3(spec["positions"], what + "[\"positions\"]");
  keep.indices = Array<uint32_t>::ensure(spec["indices"]);
  if (!keep.indices || keep.indices.ndim() != 2 || keep.indices.shape(1) != 3)
    throw py::value_error("Scene.from_meshes: " + what + "[\"indices\"] must be an (M, 3) array");
  pn_mesh mesh;
  pn_mesh_init(&mesh);
  mesh.positions = keep.positions.data();
  mesh.vertex_count = static_cast<size_t>(keep.positions.shape(0));
  mesh.indices = keep.indices.data();
  mesh.triangle_count = static_cast<size_t>(keep.indices.shape(0));
  if (spec.contains("normals") && !spec["normals"].is_none()) {
    keep.normals = rows3(spec["normals"], what + "[\"normals\"]");
    if (keep.normals.shape(0) != keep.positions.shape(0))
      throw py::value_error("Scene.from_meshes: " + what + ": normals and positions differ in length");
    mesh.normals = keep.normals.data();
  }
  if (spec.contains("transform") && !spec["transform"].is_none()) {
    // numpy's row-major (4, 4) matrix M is column-major M^T: its transpose, made contiguous, is what C takes.
    Array<float> m = Array<float>::ensure(spec["transform"]);
    if (!m || m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4)
      throw py::value_error("Scene.from_meshes: " + what + "[\"transform\"] must be a (4, 4) array");
    keep.transform = Array<float>::ensure(m.attr("T"));
    mesh.transform = keep.transform.data();
  }
  if (spec.contains("name")) keep.name = py::cast<std::string>(spec["name"]), mesh.name = keep.name.c_str();
  if (spec.contains("double_sided")) mesh.double_sided = py::cast<bool>(spec["double_sided"]) ? 1 : 0;
  return mesh;
}

Scene fromMeshes(const std::vector<py::dict>& specs, const std::vector<Light>& lights) {
  std::vector<MeshArrays> keep(specs.size());
  std::vector<pn_mesh> meshes;
  for (size_t i = 0; i < specs.size(); ++i) meshes.push_back(meshOf(specs[i], i, keep[i]));
  return Scene::fromMeshes(meshes, lights);
}

}  // namespace

void bindMeshes(py::class_<Scene>& scene) {
  scene.def_static("from_meshes", &fromMeshes, py::arg("meshes"), py::arg("lights") = std::vector<Light>{},
                   "A scene of your own triangles: a list of dicts with positions (N, 3), indices (M, 3) and "
                   "optionally normals (N, 3), transform (4, 4; world = transform @ [x, y, z, 1]), name and "
                   "double_sided; lights (Light objects) optional. No cameras: the default camera frames it.");
}

}  // namespace penumbra::python
