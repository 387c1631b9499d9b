// The Python module's parts (module.cpp: errors, contexts, scenes; render.cpp: parameters, renderer, frames;
// stages.cpp and tables.cpp: the filtering stages on numpy arrays), each binding its own names.
#pragma once

#include <pybind11/pybind11.h>

namespace penumbra::python {

void bindScene(pybind11::module_& m);
void bindRender(pybind11::module_& m);
void bindStages(pybind11::module_& m);  // stages.cpp
void bindTables(pybind11::module_& m);  // tables.cpp

}  // namespace penumbra::python
