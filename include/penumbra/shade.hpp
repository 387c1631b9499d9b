// penumbra's C++ API: techniques on the caller's own light map and G-buffer (penumbra/shade.h): a wait list in, an
// event out (owned by the caller), as the stages take them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "penumbra/context.hpp"
#include "penumbra/error.hpp"
#include "penumbra/renderer.hpp"
#include "penumbra/shade.h"
#include "penumbra/stages.hpp"

/// @file
/// penumbra::ShadeDesc, penumbra::Shader, penumbra::takesCallerMap.

namespace penumbra {
inline namespace v0 {

/// pn_shade_desc with pn_shade_desc_init()'s defaults: set its fields as the C API documents them.
struct ShadeDesc : pn_shade_desc {
  ShadeDesc() noexcept : pn_shade_desc() { pn_shade_desc_init(this); }
};

/// Shades techniques from the caller's maps on one context (pn_shader): keeps a technique's buffers across calls
/// while its parameters and the map size stay the same. Copies share the shader: use one per thread.
class Shader {
 public:
  /// A shader on `context` (retained while the shader lives).
  explicit Shader(const Context& context) {
    pn_shader* shader = nullptr;
    detail::check(pn_shader_create(context.get(), &shader));
    handle_ = Handle(shader);
  }
  /// Shades `params`' technique from `desc`'s map and G-buffer into desc.visibility (pn_shade): after `waitFor`,
  /// with `event` (may be null) completing when the visibility is written.
  void shade(const Params& params, const ShadeDesc& desc, const std::vector<cl_event>& waitFor = {},
             cl_event* event = nullptr) const {
    detail::check(pn_shade(get(), params.get(), &desc, detail::waitCount(waitFor), detail::waitList(waitFor), event));
  }
  /// What the last successful shade() recorded ("penumbra:light-fit", "penumbra:pcf-radius", ...), if anything.
  std::optional<std::string> attribute(const std::string& name) const {
    const char* value = pn_shader_attribute(get(), name.c_str());
    return value != nullptr ? std::optional<std::string>(value) : std::nullopt;
  }
  /// The C handle (not retained for the caller).
  pn_shader* get() const noexcept { return handle_.get(); }

 private:
  using Handle = detail::Handle<pn_shader, pn_shader_retain, pn_shader_release>;
  Handle handle_;
};

/// Whether the technique called `technique` shades from a caller's map; if not, `reason` (when given) says why.
inline bool takesCallerMap(const std::string& technique, std::string* reason = nullptr) {
  const char* why = nullptr;
  const bool takes = pn_technique_takes_caller_map(technique.c_str(), &why) != 0;
  if (reason != nullptr) *reason = why;
  return takes;
}

}  // namespace v0
}  // namespace penumbra
