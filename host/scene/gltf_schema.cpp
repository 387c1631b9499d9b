// Table-free glTF 2.0 schema checks: one small function per object type, helpers for the property kinds
// (non-negative integers, ids into a top-level array, fixed-size number arrays). Unknown keys are allowed
// (the glTF schema allows them); known keys must have the right type.
#include "host/scene/gltf_schema.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <numbers>
#include <sstream>
#include <string_view>
#include <utility>

namespace penumbra::detail {
namespace {

constexpr std::array<std::string_view, 4> kIgnorableExtensionPrefixes = {"KHR_materials_", "KHR_texture_",
                                                                         "EXT_texture_", "KHR_lights_punctual"};

struct Checker {
  const Json& root;
  const std::string& file;

  [[noreturn]] void fail(const std::string& ptr, const std::string& msg) const { failAt(file, ptr, msg); }

  // The object itself, its "name" and its "extensions" (an object of objects).
  void object(const Json& o, const std::string& ptr) const {
    if (!o.is_object()) fail(ptr, "expected an object, got " + brief(o));
    if (o.contains("name") && !o["name"].is_string()) fail(pointerTo(ptr, "name"), "expected a string");
    if (!o.contains("extensions")) return;
    const Json& ext = o["extensions"];
    if (!ext.is_object()) fail(pointerTo(ptr, "extensions"), "expected an object");
    for (auto it = ext.begin(); it != ext.end(); ++it)
      if (!it.value().is_object()) fail(pointerTo(pointerTo(ptr, "extensions"), it.key()), "expected an object");
  }

  const Json* get(const Json& o, const char* key, const std::string& ptr, bool required) const {
    if (o.contains(key)) return &o[key];
    if (required) fail(pointerTo(ptr, key), "missing required property");
    return nullptr;
  }

  void kind(const Json& o, const char* key, const std::string& ptr, bool ok, const char* expected) const {
    if (!ok) fail(pointerTo(ptr, key), fmt::format("expected {}, got {}", expected, brief(o[key])));
  }

  uint64_t uint(const Json& o, const char* key, const std::string& ptr, bool required = false) const {
    const Json* v = get(o, key, ptr, required);
    if (!v) return 0;
    kind(o, key, ptr, v->is_number_unsigned(), "a non-negative integer");
    // tinygltf keeps several of these (sparse counts, byte strides, component types) in an int: a larger value
    // would arrive negative ("count -2147483648"). Files are capped far below 2 GiB, so none can be that large.
    if (v->get<uint64_t>() > uint64_t{INT32_MAX})
      fail(pointerTo(ptr, key),
           fmt::format("{} is larger than {} (the largest integer this loader reads)", v->get<uint64_t>(), INT32_MAX));
    return v->get<uint64_t>();
  }

  void number(const Json& o, const char* key, const std::string& ptr) const {
    if (const Json* v = get(o, key, ptr, false))
      kind(o, key, ptr, v->is_number() && std::isfinite(v->get<double>()), "a finite number");
  }

  void string(const Json& o, const char* key, const std::string& ptr, bool required = false) const {
    if (const Json* v = get(o, key, ptr, required)) kind(o, key, ptr, v->is_string(), "a string");
  }

  void boolean(const Json& o, const char* key, const std::string& ptr) const {
    if (const Json* v = get(o, key, ptr, false)) kind(o, key, ptr, v->is_boolean(), "true or false");
  }

  // An index into the top-level array `array` ("accessors"), given at o[key] or as o itself (key null).
  void idValue(const Json& v, const char* array, const std::string& ptr) const {
    if (!v.is_number_unsigned()) fail(ptr, "expected an index (a non-negative integer), got " + brief(v));
    const size_t n = root.contains(array) && root[array].is_array() ? root[array].size() : 0;
    if (v.get<uint64_t>() >= n)
      fail(ptr, fmt::format("no element {} in {} (the file has {})", v.get<uint64_t>(), array, n));
  }
  void id(const Json& o, const char* key, const char* array, const std::string& ptr, bool required = false) const {
    if (const Json* v = get(o, key, ptr, required)) idValue(*v, array, pointerTo(ptr, key));
  }
  void ids(const Json& o, const char* key, const char* array, const std::string& ptr) const {
    const Json* v = get(o, key, ptr, false);
    if (!v) return;
    kind(o, key, ptr, v->is_array(), "an array");
    for (size_t i = 0; i < v->size(); ++i) idValue((*v)[i], array, pointerTo(pointerTo(ptr, key), i));
  }

  void numbers(const Json& o, const char* key, size_t size, const std::string& ptr) const {
    const Json* v = get(o, key, ptr, false);
    if (!v) return;
    kind(o, key, ptr, v->is_array() && (size == 0 || v->size() == size),
         size ? fmt::format("an array of {} numbers", size).c_str() : "an array of numbers");
    for (size_t i = 0; i < v->size(); ++i)
      if (!(*v)[i].is_number() || !std::isfinite((*v)[i].get<double>()))
        fail(pointerTo(pointerTo(ptr, key), i), "expected a finite number, got " + brief((*v)[i]));
  }

  // Calls fn(element, pointer) for every element of the top-level array `key`, each an object.
  template <class Fn>
  void each(const Json& o, const char* key, const std::string& ptr, Fn fn) const {
    const Json* v = get(o, key, ptr, false);
    if (!v) return;
    kind(o, key, ptr, v->is_array(), "an array");
    for (size_t i = 0; i < v->size(); ++i) {
      const std::string p = pointerTo(pointerTo(ptr, key), i);
      object((*v)[i], p);
      fn((*v)[i], p);
    }
  }
  template <class Fn>
  void child(const Json& o, const char* key, const std::string& ptr, bool required, Fn fn) const {
    if (const Json* v = get(o, key, ptr, required)) {
      object(*v, pointerTo(ptr, key));
      fn(*v, pointerTo(ptr, key));
    }
  }

  void node(const Json& n, const std::string& p) const {
    id(n, "camera", "cameras", p), id(n, "skin", "skins", p), id(n, "mesh", "meshes", p);
    ids(n, "children", "nodes", p);
    numbers(n, "matrix", 16, p), numbers(n, "rotation", 4, p), numbers(n, "scale", 3, p);
    numbers(n, "translation", 3, p), numbers(n, "weights", 0, p);
  }

  void attributeMap(const Json& a, const std::string& p) const {
    if (!a.is_object()) fail(p, "expected an object");
    for (auto it = a.begin(); it != a.end(); ++it) idValue(it.value(), "accessors", pointerTo(p, it.key()));
  }

  void primitive(const Json& pr, const std::string& p) const {
    const Json* attributes = get(pr, "attributes", p, true);
    attributeMap(*attributes, pointerTo(p, "attributes"));
    id(pr, "indices", "accessors", p), id(pr, "material", "materials", p);
    if (uint(pr, "mode", p) > 6) fail(pointerTo(p, "mode"), "expected a primitive mode 0..6");
    if (const Json* targets = get(pr, "targets", p, false)) {
      kind(pr, "targets", p, targets->is_array(), "an array");
      for (size_t i = 0; i < targets->size(); ++i) attributeMap((*targets)[i], pointerTo(pointerTo(p, "targets"), i));
    }
  }

  void mesh(const Json& m, const std::string& p) const {
    const Json* prims = get(m, "primitives", p, true);
    kind(m, "primitives", p, prims->is_array() && !prims->empty(), "a non-empty array");
    each(m, "primitives", p, [&](const Json& pr, const std::string& pp) { primitive(pr, pp); });
    numbers(m, "weights", 0, p);
  }

  void accessor(const Json& a, const std::string& p) const {
    id(a, "bufferView", "bufferViews", p), uint(a, "byteOffset", p), boolean(a, "normalized", p);
    const uint64_t type = uint(a, "componentType", p, true);
    if (type < 5120 || type > 5126 || type == 5124)
      fail(pointerTo(p, "componentType"), fmt::format("invalid component type {}", type));
    if (uint(a, "count", p, true) == 0) fail(pointerTo(p, "count"), "must be at least 1");
    string(a, "type", p, true);
    static constexpr std::array<std::string_view, 7> kTypes = {"SCALAR", "VEC2", "VEC3", "VEC4",
                                                               "MAT2",   "MAT3", "MAT4"};
    if (std::find(kTypes.begin(), kTypes.end(), a["type"].get<std::string>()) == kTypes.end())
      fail(pointerTo(p, "type"), "invalid accessor type " + brief(a["type"]));
    numbers(a, "min", 0, p), numbers(a, "max", 0, p);
    child(a, "sparse", p, false, [&](const Json& s, const std::string& sp) {
      if (uint(s, "count", sp, true) == 0) fail(pointerTo(sp, "count"), "must be at least 1");
      child(s, "indices", sp, true, [&](const Json& i, const std::string& ip) {
        id(i, "bufferView", "bufferViews", ip, true), uint(i, "byteOffset", ip), uint(i, "componentType", ip, true);
      });
      child(s, "values", sp, true, [&](const Json& v, const std::string& vp) {
        id(v, "bufferView", "bufferViews", vp, true), uint(v, "byteOffset", vp);
      });
    });
  }

  void textureInfo(const Json& m, const char* key, const std::string& p) const {
    child(m, key, p, false, [&](const Json& t, const std::string& tp) {
      uint(t, "texCoord", tp), number(t, "scale", tp), number(t, "strength", tp), id(t, "index", "textures", tp, true);
      if (!t.contains("extensions") || !t["extensions"].contains("KHR_texture_transform")) return;
      const std::string xp = pointerTo(pointerTo(tp, "extensions"), "KHR_texture_transform");
      const Json& x = t["extensions"]["KHR_texture_transform"];
      numbers(x, "offset", 2, xp), number(x, "rotation", xp), numbers(x, "scale", 2, xp), uint(x, "texCoord", xp);
    });
  }

  // Sec. 3.6.1.1: a buffer's data URI is base64 of application/octet-stream (or application/gltf-buffer), and holds
  // at least byteLength bytes.
  void dataUri(const std::string& uri, uint64_t byteLength, const std::string& ptr) const {
    const size_t comma = uri.find(',');
    const std::string_view head = std::string_view(uri).substr(0, comma);
    if (comma == std::string::npos ||
        (head != "data:application/octet-stream;base64" && head != "data:application/gltf-buffer;base64"))
      fail(ptr, fmt::format("a buffer's data URI starts \"data:application/octet-stream;base64,\" (or "
                            "application/gltf-buffer), not \"{}\"",
                            visible(head.substr(0, 60))));
    const std::string_view data = std::string_view(uri).substr(comma + 1);
    const size_t padding = data.size() - std::min(data.find_last_not_of('=') + 1, data.size());
    for (size_t i = 0; i < data.size() - padding; ++i)
      if (!std::isalnum(static_cast<unsigned char>(data[i])) && data[i] != '+' && data[i] != '/')
        fail(ptr, fmt::format("its base64 holds {} at character {}", visible(data.substr(i, 1)), i));
    if (data.size() % 4 != 0 || padding > 2)
      fail(ptr, fmt::format("its base64 is {} characters long, not a multiple of 4 (truncated?)", data.size()));
    const uint64_t bytes = data.size() / 4 * 3 - padding;
    if (bytes < byteLength)
      fail(ptr,
           fmt::format("its base64 decodes to {} bytes, fewer than the buffer's byteLength {}", bytes, byteLength));
  }

  // glTF 2.0 sec. 5.6-5.8: an animation's structure, checked whether or not --time plays it (its keys are read then).
  void animation(const Json& a, const std::string& p) const {
    for (const char* key : {"channels", "samplers"}) {
      const Json* v = get(a, key, p, true);
      kind(a, key, p, v->is_array() && !v->empty(), "a non-empty array");
    }
    const size_t samplers = a["samplers"].size();
    each(a, "samplers", p, [&](const Json& s, const std::string& sp) {
      id(s, "input", "accessors", sp, true), id(s, "output", "accessors", sp, true), string(s, "interpolation", sp);
    });
    each(a, "channels", p, [&](const Json& c, const std::string& cp) {
      const uint64_t sampler = uint(c, "sampler", cp, true);
      if (sampler >= samplers)
        fail(pointerTo(cp, "sampler"), fmt::format("no sampler {} in this animation (it has {})", sampler, samplers));
      child(c, "target", cp, true,
            [&](const Json& t, const std::string& tp) { id(t, "node", "nodes", tp), string(t, "path", tp, true); });
    });
  }

  // One of `allowed` at o[key] when present (glTF's enumerations of strings and integers).
  template <class T>
  void oneOf(const Json& o, const char* key, const std::string& ptr, std::initializer_list<T> allowed) const {
    if (!o.contains(key)) return;
    for (const T& a : allowed)
      if (o[key] == a) return;
    std::string list;
    for (const T& a : allowed) list += fmt::format("{}{}", list.empty() ? "" : ", ", Json(a).dump());
    fail(pointerTo(ptr, key), fmt::format("expected one of {}, got {}", list, brief(o[key])));
  }

  void material(const Json& m, const std::string& p) const {
    child(m, "pbrMetallicRoughness", p, false, [&](const Json& pbr, const std::string& pp) {
      numbers(pbr, "baseColorFactor", 4, pp), number(pbr, "metallicFactor", pp), number(pbr, "roughnessFactor", pp);
      if (pbr.contains("baseColorFactor"))
        for (size_t i = 0; i < 4; ++i)
          if (!(pbr["baseColorFactor"][i].get<double>() >= 0.0 && pbr["baseColorFactor"][i].get<double>() <= 1.0))
            fail(pointerTo(pointerTo(pp, "baseColorFactor"), i), "expected a number in [0, 1]");
      textureInfo(pbr, "baseColorTexture", pp), textureInfo(pbr, "metallicRoughnessTexture", pp);
    });
    textureInfo(m, "normalTexture", p), textureInfo(m, "occlusionTexture", p), textureInfo(m, "emissiveTexture", p);
    numbers(m, "emissiveFactor", 3, p), string(m, "alphaMode", p), boolean(m, "doubleSided", p);
    oneOf<std::string>(m, "alphaMode", p, {"OPAQUE", "MASK", "BLEND"});
    bounded(m, "alphaCutoff", p, false, 0.0, true);
  }

  // glTF 2.0 sec. 5.26: filters 9728 NEAREST, 9729 LINEAR, 9984..9987 the mipmapped ones (minFilter only); wraps
  // 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT, 10497 REPEAT.
  void sampler(const Json& s, const std::string& p) const {
    uint(s, "magFilter", p), uint(s, "minFilter", p), uint(s, "wrapS", p), uint(s, "wrapT", p);
    oneOf<int>(s, "magFilter", p, {9728, 9729});
    oneOf<int>(s, "minFilter", p, {9728, 9729, 9984, 9985, 9986, 9987});
    oneOf<int>(s, "wrapS", p, {33071, 33648, 10497}), oneOf<int>(s, "wrapT", p, {33071, 33648, 10497});
  }

  // A number at o[key] above `lo` (or at least lo when `inclusive`), or missing when not `required`.
  void bounded(const Json& o, const char* key, const std::string& ptr, bool required, double lo, bool inclusive) const {
    const Json* v = get(o, key, ptr, required);
    if (!v) return;
    const bool ok = v->is_number() && std::isfinite(v->get<double>()) &&
                    (inclusive ? v->get<double>() >= lo : v->get<double>() > lo);
    kind(o, key, ptr, ok, inclusive ? "a finite number >= 0" : "a finite number > 0");
  }

  // glTF 2.0 sec. 5.12-5.14: a camera's type and the projection object it names, with every range checked here
  // (zfar > znear too) so the importer (gltf_camera.cpp) reads plain valid numbers.
  void camera(const Json& c, const std::string& p) const {
    string(c, "type", p, true);
    const std::string type = c["type"].get<std::string>();
    if (type != "perspective" && type != "orthographic")
      fail(pointerTo(p, "type"), "expected \"perspective\" or \"orthographic\", got " + brief(c["type"]));
    child(c, type.c_str(), p, true, [&](const Json& proj, const std::string& pp) {
      if (type == "perspective") {
        bounded(proj, "yfov", pp, true, 0.0, false), bounded(proj, "aspectRatio", pp, false, 0.0, false);
        bounded(proj, "znear", pp, true, 0.0, false), bounded(proj, "zfar", pp, false, 0.0, false);
        if (proj["yfov"].get<double>() >= std::numbers::pi)
          fail(pointerTo(pp, "yfov"), fmt::format("{} radians is not below pi", proj["yfov"].get<double>()));
      } else {
        for (const char* key : {"xmag", "ymag"}) {  // sec. 5.14: MUST NOT be zero, SHOULD NOT be negative
          const Json* v = get(proj, key, pp, true);
          kind(proj, key, pp, v->is_number() && std::isfinite(v->get<double>()) && v->get<double>() != 0.0,
               "a finite non-zero number");
        }
        bounded(proj, "znear", pp, true, 0.0, true), bounded(proj, "zfar", pp, true, 0.0, false);
      }
      if (proj.contains("zfar") && !(proj["zfar"].get<double>() > proj["znear"].get<double>()))
        fail(pointerTo(pp, "zfar"),
             fmt::format("{} is not beyond znear {}", proj["zfar"].get<double>(), proj["znear"].get<double>()));
    });
  }

  void document() const {
    object(root, "");
    child(root, "asset", "", true, [&](const Json& a, const std::string& p) {
      string(a, "version", p, true), string(a, "minVersion", p);
      if (a["version"].get<std::string>().rfind("2.", 0) != 0)
        fail(pointerTo(p, "version"),
             "glTF version " + a["version"].get<std::string>() + " is not supported (2.x only)");
      // Sec. 5.2: minVersion, when given, is at most version; a loader refuses assets whose minVersion it does not
      // meet (this one reads 2.0).
      if (a.contains("minVersion")) {
        const auto parts = [&](const std::string& v, const char* key) {
          unsigned major = 0, minor = 0;
          char dot = 0;
          std::istringstream in(v);
          if (!(in >> major >> dot >> minor) || dot != '.' || !in.eof())
            fail(pointerTo(p, key), "expected MAJOR.MINOR, got " + brief(a[key]));
          return std::pair{major, minor};
        };
        const auto min = parts(a["minVersion"].get<std::string>(), "minVersion");
        if (min > parts(a["version"].get<std::string>(), "version"))
          fail(pointerTo(p, "minVersion"), fmt::format("{} is above version {}", a["minVersion"].get<std::string>(),
                                                       a["version"].get<std::string>()));
        if (min > std::pair{2u, 0u})
          fail(pointerTo(p, "minVersion"),
               fmt::format("the asset needs glTF {}; this loader reads 2.0", a["minVersion"].get<std::string>()));
      }
    });
    // Every top-level array's own type first, so an index into one that is not an array ("nodes": "all") names it
    // rather than the index.
    for (const char* key : {"scenes", "nodes", "meshes", "accessors", "bufferViews", "buffers", "materials", "textures",
                            "images", "samplers", "cameras", "skins", "animations"})
      if (const Json* v = get(root, key, "", false)) kind(root, key, "", v->is_array(), "an array");
    id(root, "scene", "scenes", "");
    each(root, "scenes", "", [&](const Json& s, const std::string& p) { ids(s, "nodes", "nodes", p); });
    each(root, "nodes", "", [&](const Json& n, const std::string& p) { node(n, p); });
    each(root, "meshes", "", [&](const Json& m, const std::string& p) { mesh(m, p); });
    each(root, "accessors", "", [&](const Json& a, const std::string& p) { accessor(a, p); });
    each(root, "bufferViews", "", [&](const Json& v, const std::string& p) {
      id(v, "buffer", "buffers", p, true), uint(v, "byteOffset", p), uint(v, "target", p);
      if (const uint64_t stride = uint(v, "byteStride", p);
          v.contains("byteStride") && (stride < 4 || stride > 252 || stride % 4))
        fail(pointerTo(p, "byteStride"), fmt::format("{} is not a multiple of 4 in 4..252 (sec. 5.11)", stride));
      if (uint(v, "byteLength", p, true) == 0) fail(pointerTo(p, "byteLength"), "must be at least 1");
    });
    each(root, "buffers", "", [&](const Json& b, const std::string& p) {
      string(b, "uri", p);
      const uint64_t length = uint(b, "byteLength", p, true);
      if (b.contains("uri") && b["uri"].get<std::string>().rfind("data:", 0) == 0)
        dataUri(b["uri"].get<std::string>(), length, pointerTo(p, "uri"));
    });
    each(root, "materials", "", [&](const Json& m, const std::string& p) { material(m, p); });
    each(root, "textures", "",
         [&](const Json& t, const std::string& p) { id(t, "sampler", "samplers", p), id(t, "source", "images", p); });
    each(root, "images", "", [&](const Json& i, const std::string& p) {
      string(i, "uri", p), string(i, "mimeType", p), id(i, "bufferView", "bufferViews", p);
    });
    each(root, "samplers", "", [&](const Json& s, const std::string& p) { sampler(s, p); });
    each(root, "cameras", "", [&](const Json& c, const std::string& p) { camera(c, p); });
    each(root, "skins", "", [](const Json&, const std::string&) {});
    each(root, "animations", "", [&](const Json& a, const std::string& p) { animation(a, p); });
  }

  // KHR_lights_punctual: tinygltf 2.7 keeps mistyped optional light properties at their defaults and reads a
  // node's light only as a raw extension value, so every property and node reference is checked here.
  void lightsPunctual() const {
    const Json* ext = root.contains("extensions") ? get(root["extensions"], "KHR_lights_punctual", "", false) : nullptr;
    const std::string extPtr = "/extensions/KHR_lights_punctual";
    if (ext) each(*ext, "lights", extPtr, [&](const Json& l, const std::string& p) { light(l, p); });
    const size_t count = ext && ext->contains("lights") ? (*ext)["lights"].size() : 0;
    if (!root.contains("nodes")) return;
    for (size_t i = 0; i < root["nodes"].size(); ++i) {
      const Json& n = root["nodes"][i];
      if (!n.contains("extensions") || !n["extensions"].contains("KHR_lights_punctual")) continue;
      const std::string p = pointerTo(pointerTo(pointerTo("/nodes", i), "extensions"), "KHR_lights_punctual");
      const Json* index = get(n["extensions"]["KHR_lights_punctual"], "light", p, true);
      if (!index->is_number_unsigned()) fail(pointerTo(p, "light"), "expected a light index, got " + brief(*index));
      if (index->get<uint64_t>() >= count)
        fail(pointerTo(p, "light"),
             fmt::format("no light {} in KHR_lights_punctual (the file has {})", index->get<uint64_t>(), count));
    }
  }

  void light(const Json& l, const std::string& p) const {
    string(l, "type", p, true);
    const std::string type = l["type"].get<std::string>();
    if (type != "spot" && type != "directional" && type != "point")
      fail(pointerTo(p, "type"), "expected \"spot\", \"directional\" or \"point\", got " + brief(l["type"]));
    numbers(l, "color", 3, p), bounded(l, "intensity", p, false, 0.0, true), number(l, "range", p);
    if (l.contains("range") && !(l["range"].get<double>() > 0.0))
      fail(pointerTo(p, "range"), "must be positive (leave it out for an unlimited range)");
    if (type == "spot")
      child(l, "spot", p, true, [&](const Json& s, const std::string& sp) {
        number(s, "innerConeAngle", sp), number(s, "outerConeAngle", sp);
      });
  }

  void requiredExtensions() const {
    for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
      const Json* v = get(root, key, "", false);
      if (v && (!v->is_array() || !std::all_of(v->begin(), v->end(), [](const Json& e) { return e.is_string(); })))
        fail(pointerTo("", key), "expected an array of strings");
    }
    if (!root.contains("extensionsRequired")) return;
    for (const Json& e : root["extensionsRequired"]) {
      const std::string name = e.get<std::string>();
      const bool ignorable = std::any_of(kIgnorableExtensionPrefixes.begin(), kIgnorableExtensionPrefixes.end(),
                                         [&](std::string_view prefix) { return name.rfind(prefix, 0) == 0; });
      if (!ignorable)
        throw SceneError(
            fmt::format("{}: extension {} is required but not supported (only material, texture and "
                        "light extensions can be ignored)",
                        file, name));
    }
  }
};

}  // namespace

void checkGltfJson(const Json& doc, const std::string& file) {
  const Checker checker{doc, file};
  if (!doc.is_object()) failAt(file, "", "expected a glTF JSON object");
  checker.requiredExtensions();
  checker.document();
  checker.lightsPunctual();
}

}  // namespace penumbra::detail
