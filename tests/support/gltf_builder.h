// Small glTF files written by the tests themselves: a triangle soup (flat normals) as mesh 0 on node 0, plus the
// nodes and cameras a test adds as JSON, written as NAME.gltf + NAME.bin into a folder.
#pragma once

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
    std::ofstream(dir / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(float)));
    std::ofstream(dir / (name + ".gltf")) << doc.dump(1);
    return (dir / (name + ".gltf")).string();
  }

 private:
  std::vector<glm::vec3> soup_;
  Json doc_;
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
