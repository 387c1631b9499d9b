// Plain C++ references of kernels/cube.cl, written from the rule's definition without kernels/shared/cube.h: the
// face of a direction (largest |component|, the first such axis in x, y, z order, + unless that component is
// negative; NaN and zero: +X), each face's pixels, the face G-buffer's kept pixels and the visibility copy.
#pragma once

#include <cstdint>
#include <vector>

#include <CL/cl_platform.h>
#include <glm/glm.hpp>

namespace penumbra::ref {

// 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z.
int cubeFace(double x, double y, double z);

// cube_classify: -1 for background (w == 0), else the face of (p - light) with the difference taken in float, as the
// kernel takes it.
std::vector<int32_t> cubeClassify(const std::vector<cl_float4>& position, const glm::vec3& light);

// cube_mask's kept pixels (rows of `width`): the face's own, and covered pixels within the face's window (in front,
// |right|, |up| <= tangent * forward, in double) with a pixel of the face in their 3x3 block.
std::vector<bool> cubeKept(const std::vector<cl_float4>& position, const std::vector<int32_t>& faces, int width,
                           int height, const glm::vec3& light, int face, double tangent);

// Directions where the rule's order matters: exact ties between two or three axes, signed zeros, the zero vector,
// neighbours of ties one ulp apart, infinities, NaN in each component, subnormal and huge magnitudes.
std::vector<glm::vec3> adversarialDirections();
// `count` random directions, every few on a face edge or corner (components of equal magnitude), magnitudes
// 2^-20 .. 2^20.
std::vector<glm::vec3> randomDirections(size_t count, uint32_t seed);
// Positions light + d (w = 1) for `directions`, every 7th one background (w = 0).
std::vector<cl_float4> positionsAround(const glm::vec3& light, const std::vector<glm::vec3>& directions);

}  // namespace penumbra::ref
