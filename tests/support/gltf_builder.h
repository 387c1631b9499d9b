// Small glTF files written by the tests themselves: a triangle soup (flat normals) as mesh 0 on node 0, plus the
// nodes and cameras a test adds as JSON, written as NAME.gltf + NAME.bin into a folder.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace penumbra::test {

class GltfBuilder {
 public:
  using Json = nlohmann::json;

  // `soup`: three positions per triangle, counter-clockwise front faces.
  explicit GltfBuilder(std::vector<glm::vec3> soup) : soup_(std::move(soup)) {
    doc_ = {
        {"asset", {{"version", "2.0"}}},
        {"scene", 0},
        {"scenes", Json::array({{{"nodes", Json::array({0})}}})},
        {"nodes", Json::array({{{"name", "geometry"}, {"mesh", 0}}})},
        {"meshes", Json::array({{{"primitives", Json::array({{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}}})}}})}};
  }

  // Adds a node (a root of scene 0 unless `root` is false: make it some node's child yourself); returns its index.
  int addNode(const Json& node, bool root = true) {
    doc_["nodes"].push_back(node);
    const int index = static_cast<int>(doc_["nodes"].size()) - 1;
    if (root) doc_["scenes"][0]["nodes"].push_back(index);
    return index;
  }
  int addCamera(const Json& camera) {
    if (!doc_.contains("cameras")) doc_["cameras"] = Json::array();
    doc_["cameras"].push_back(camera);
    return static_cast<int>(doc_["cameras"].size()) - 1;
  }
  Json& doc() { return doc_; }

  // Adds an accessor of `type` ("SCALAR", "VEC3", "MAT4", ...) over `values`, stored as FLOAT, or as
  // `componentType` (5120 BYTE ... 5123 UNSIGNED_SHORT) when given, `normalized` or not; returns its index. The data
  // goes after the geometry in NAME.bin, in a bufferView of its own (4-byte aligned).
  int addAccessor(const std::vector<double>& values, const std::string& type, int componentType = 5126,
                  bool normalized = false) {
    extras_.push_back({values, type, componentType, normalized});
    return 2 + static_cast<int>(extras_.size()) - 1;
  }

  // Writes DIR/NAME.gltf and DIR/NAME.bin; returns the .gltf path.
  std::string write(const std::filesystem::path& dir, const std::string& name) const {
    std::vector<float> data;
    for (const glm::vec3& p : soup_) data.insert(data.end(), {p.x, p.y, p.z});
    for (size_t t = 0; t + 2 < soup_.size(); t += 3) {
      const glm::vec3 n = glm::normalize(glm::cross(soup_[t + 1] - soup_[t], soup_[t + 2] - soup_[t]));
      for (int k = 0; k < 3; ++k) data.insert(data.end(), {n.x, n.y, n.z});
    }
    const size_t half = soup_.size() * 12, count = soup_.size();
    Json doc = doc_;
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& p : soup_) lo = glm::min(lo, p), hi = glm::max(hi, p);
    doc["buffers"] = Json::array({{{"uri", name + ".bin"}, {"byteLength", 2 * half}}});
    doc["bufferViews"] =
        Json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 2 * half}, {"byteStride", 12}}});
    doc["accessors"] = Json::array(
        {{{"bufferView", 0},
          {"componentType", 5126},
          {"count", count},
          {"type", "VEC3"},
          {"min", {lo.x, lo.y, lo.z}},
          {"max", {hi.x, hi.y, hi.z}}},
         {{"bufferView", 0}, {"byteOffset", half}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}}});
    std::vector<unsigned char> bytes(data.size() * sizeof(float));
    std::memcpy(bytes.data(), data.data(), bytes.size());
    for (const Extra& e : extras_) appendExtra(e, doc, bytes);
    doc["buffers"][0]["byteLength"] = bytes.size();
    std::ofstream(dir / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    std::ofstream(dir / (name + ".gltf")) << doc.dump(1);
    return (dir / (name + ".gltf")).string();
  }

 private:
  struct Extra {
    std::vector<double> values;
    std::string type;
    int componentType;
    bool normalized;
  };

  static int width(const std::string& type) {
    return type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 16;
  }

  static void appendExtra(const Extra& e, Json& doc, std::vector<unsigned char>& bytes) {
    while (bytes.size() % 4 != 0) bytes.push_back(0);
    const size_t offset = bytes.size();
    const size_t size = e.componentType == 5126 ? 4 : e.componentType <= 5121 ? 1 : 2;
    for (double v : e.values) {
      unsigned char raw[4] = {};
      if (e.componentType == 5126) {
        const float f = static_cast<float>(v);
        std::memcpy(raw, &f, 4);
      } else if (size == 1) {
        raw[0] = static_cast<unsigned char>(static_cast<int>(v) & 0xff);
      } else {
        const auto h = static_cast<uint16_t>(static_cast<int>(v) & 0xffff);
        std::memcpy(raw, &h, 2);
      }
      bytes.insert(bytes.end(), raw, raw + size);
    }
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes.size() - offset}});
    Json accessor = {{"bufferView", doc["bufferViews"].size() - 1},
                     {"componentType", e.componentType},
                     {"count", e.values.size() / static_cast<size_t>(width(e.type))},
                     {"type", e.type}};
    if (e.normalized) accessor["normalized"] = true;
    doc["accessors"].push_back(accessor);
  }

  std::vector<glm::vec3> soup_;
  Json doc_;
  std::vector<Extra> extras_;
};

// A square in the y = `y` plane, facing +Y, of half size `half` around (cx, cz).
inline void addQuadY(std::vector<glm::vec3>& soup, float y, float half, float cx = 0.0f, float cz = 0.0f) {
  const glm::vec3 a(cx - half, y, cz - half), b(cx - half, y, cz + half), c(cx + half, y, cz + half),
      d(cx + half, y, cz - half);
  soup.insert(soup.end(), {a, b, c, a, c, d});
}

// An axis-aligned box [lo, hi], outward-facing.
inline void addBox(std::vector<glm::vec3>& soup, const glm::vec3& lo, const glm::vec3& hi) {
  auto corner = [&](int i) { return glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z); };
  // Faces as corner indices, counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces)
    soup.insert(soup.end(), {corner(f[0]), corner(f[1]), corner(f[2]), corner(f[0]), corner(f[2]), corner(f[3])});
}

}  // namespace penumbra::test
