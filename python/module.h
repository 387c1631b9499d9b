// The Python module's parts (module.cpp: errors, contexts, scenes; render.cpp: parameters, renderer, frames;
// meshes.cpp: scenes of numpy arrays; stages.cpp and tables.cpp: the filtering stages on numpy arrays), each binding
// its own names.
#pragma once

#include <pybind11/pybind11.h>

#include <penumbra/scene.hpp>

namespace penumbra::python {

void bindScene(pybind11::module_& m);
void bindMeshes(pybind11::class_<Scene>& scene);  // meshes.cpp: Scene.from_meshes
void bindRender(pybind11::module_& m);
void bindStages(pybind11::module_& m);  // stages.cpp
void bindTables(pybind11::module_& m);  // tables.cpp

}  // namespace penumbra::python
