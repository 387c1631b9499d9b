# penumbra_precompile_headers(TARGET [HEADER...]): the heavy third-party and standard headers almost every file of
# TARGET includes, compiled once per target instead of once per unity batch (docs/tests.md, Build time). Only for
# targets of several translation units: a single-file target pays the precompilation and saves nothing. Headers
# that a file compiles with its own macros (tiny_gltf.h, stb_image.h, nlohmann/json.hpp through tinygltf) stay out.
set(PENUMBRA_PRECOMPILED_COMMON
    <algorithm> <array> <cmath> <cstdint> <filesystem> <functional> <map> <memory> <optional> <span> <stdexcept>
    <string> <string_view> <unordered_map> <utility> <vector>
    <CL/opencl.hpp> <fmt/format.h> <glm/glm.hpp>)

function(penumbra_precompile_headers target)
  if(PENUMBRA_PRECOMPILED_HEADERS)
    target_precompile_headers(${target} PRIVATE ${PENUMBRA_PRECOMPILED_COMMON} ${ARGN})
  endif()
endfunction()
