// A point light's six cube faces: classify the pixels once, then per face its G-buffer, its receivers, the
// technique's render of the face's spot light, and the copy of its own pixels.
#include "host/pipeline/point_light.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "host/views/cube.h"
#include "host/views/light_fit.h"

namespace penumbra {
namespace {

// Appends a face's attribute values to the light's: "+X: value; -Y: value".
void mergeAttributes(std::map<std::string, std::string>& into, const std::map<std::string, std::string>& face,
                     const std::string& faceName) {
  for (const auto& [key, value] : face) {
    std::string& all = into[key];
    all += fmt::format("{}{}: {}", all.empty() ? "" : "; ", faceName, value);
  }
}

}  // namespace

void CubeShadows::render(ShadowFrame& frame, Technique& technique, int size, float cubeGuard,
                         Buffer<float>& visibility) {
  const Light& point = frame.light;
  if (point.type != LightType::Point) throw std::invalid_argument("CubeShadows: not a point light");
  Context& ctx = frame.ctx;
  // The guard as cube_window_tangent clamps it, for the header.
  const float guard = std::clamp(cubeGuard, 0.0f,
                                 CUBE_MAX_GUARD_FRACTION * static_cast<float>(size));
  const float tangent = cube_window_tangent(guard, size);
  const Bounds bounds = frame.scene.bounds();
  classifyCubeFaces(ctx, frame.gbuffer, point.position, faces_);
  faceVisibility_.allocate(ctx, visibility.size());
  visibility.fill(ctx, 1.0f);  // background: no face owns it

  std::map<std::string, std::string> attributes;
  std::string drawn, empty;
  for (int face = 0; face < CUBE_FACES; ++face) {
    const std::string name = cubeFaceName(face);
    maskCubeFace(ctx, frame.gbuffer, faces_, point.position, face, tangent, face_);
    const Light spot = cubeFaceLight(point, face, tangent);
    const ReceiverBounds receivers = reduceReceivers(ctx, face_, lightEyeMatrix(spot, bounds), true);
    if (receivers.empty) {  // no pixel of the camera's lies on this face: nothing to draw or copy
      empty += (empty.empty() ? "" : " ") + name;
      continue;
    }
    ShadowFrame faceFrame{ctx, frame.raster, frame.scene, spot, frame.camera, face_, receivers};
    faceFrame.pointLight = &point;
    faceFrame.solids = frame.solids;
    technique.render(faceFrame, faceVisibility_);
    selectCubeFace(ctx, faces_, faceVisibility_, face, visibility);
    mergeAttributes(attributes, faceFrame.attributes, name);
    drawn += (drawn.empty() ? "" : " ") + name;
  }
  frame.attributes.insert(attributes.begin(), attributes.end());
  frame.attributes["penumbra:cube"] =
      fmt::format("guard {:g} texels of {} (window tangent {:.6g}, fov {:.6g} deg), faces drawn: {}{}", guard, size,
                  tangent, 2.0 * glm::degrees(std::atan(static_cast<double>(tangent))), drawn.empty() ? "none" : drawn,
                  empty.empty() ? "" : "; no pixels: " + empty);
}

}  // namespace penumbra
