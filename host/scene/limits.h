// The limits every way into a frame shares (command line, scene files, glTF cameras, the library), so that a value
// one of them accepts is never refused later by another.
#pragma once

namespace penumbra {

// Image width and height in pixels: the rasterizer's largest viewport (RASTER_MAX_VIEWPORT, static_assert in
// host/pipeline/frame_check.cpp).
inline constexpr int kMaxImageSide = 8192;

// World coordinates (positions, eyes, targets, ground heights) in [-kMaxCoordinate, kMaxCoordinate]: squared
// distances between two such points (3 * (2e18)^2 ~ 1.2e37) stay finite in float, so view and projection matrices,
// light fits and bounds are finite wherever the inputs are within it.
inline constexpr double kMaxCoordinate = 1e18;
inline bool inCoordinateRange(double v) { return v >= -kMaxCoordinate && v <= kMaxCoordinate; }  // false for NaN
inline bool inCoordinateRange(double x, double y, double z) {
  return inCoordinateRange(x) && inCoordinateRange(y) && inCoordinateRange(z);
}

}  // namespace penumbra
