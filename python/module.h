// The Python module's parts (module.cpp: errors, contexts, scenes; render.cpp: parameters, renderer, frames;
// meshes.cpp: scenes of numpy arrays; stages.cpp and tables.cpp: the filtering stages on numpy arrays; shade.cpp:
// techniques on the caller's map and G-buffer), each binding
// its own names.
#pragma once

#include <pybind11/pybind11.h>

#include <penumbra/renderer.hpp>
#include <penumbra/scene.hpp>
#include <string>

namespace penumbra::python {

void bindScene(pybind11::module_& m);
void bindMeshes(pybind11::class_<Scene>& scene);  // meshes.cpp: Scene.from_meshes
void bindRender(pybind11::module_& m);
void bindStages(pybind11::module_& m);  // stages.cpp
void bindTables(pybind11::module_& m);  // tables.cpp
void bindShade(pybind11::module_& m);   // shade.cpp: Shader, techniques on the caller's map and G-buffer

// render.cpp: a technique's Params from a dictionary of values (str as is, bool as 0/1, numbers with 17 digits).
Params makeParams(const std::string& technique, const pybind11::dict& values);

}  // namespace penumbra::python
