// glTF materials as shadows see them (host/scene/gltf_materials.cpp, gltf_images.cpp): a quad written by the test
// with a PNG made by stb_image_write, read back with its alphaMode, cutoff, factor, texture (external file, data: URI,
// GLB buffer view), texCoord set, KHR_texture_transform, sampler and doubleSided; textures of opaque materials left
// undecoded; images without alpha; BLEND's cutoff; the texture budget; and one clear error per malformed case.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "host/scene/gltf_loader.h"
#include "scene_test_util.h"
#include "tests/support/temp_dir.h"

#define STB_IMAGE_WRITE_STATIC  // a private copy: cannot clash with the library's
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace penumbra {
namespace scene_gltf_alpha_test {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using test::throwsWith;

// A PNG of `channels` channels (4: RGBA, 3: RGB) in memory; texel i's alpha is alphas[i].
std::vector<unsigned char> png(int w, int h, int channels, const std::vector<uint8_t>& alphas) {
  std::vector<unsigned char> pixels(static_cast<size_t>(w) * h * channels, 90);
  if (channels == 4)
    for (size_t i = 0; i < alphas.size(); ++i) pixels[i * 4 + 3] = alphas[i];
  std::vector<unsigned char> out;
  stbi_write_png_to_func(
      [](void* context, void* data, int size) {
        auto* bytes = static_cast<std::vector<unsigned char>*>(context);
        bytes->insert(bytes->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
      },
      &out, w, h, channels, pixels.data(), w * channels);
  return out;
}

std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = uint32_t{bytes[i]} << 16 | (i + 1 < bytes.size() ? uint32_t{bytes[i + 1]} << 8 : 0) |
                       (i + 2 < bytes.size() ? bytes[i + 2] : 0);
    out += kDigits[n >> 18 & 63], out += kDigits[n >> 12 & 63];
    out += i + 1 < bytes.size() ? kDigits[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return out;
}

const std::vector<uint8_t> kAlphas = {0, 40, 80, 120, 160, 200, 240, 255};  // the 4x2 texture's alphas
const std::vector<glm::vec2> kUv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
const std::vector<glm::u8vec2> kUv1 = {{0, 0}, {255, 0}, {255, 255}, {0, 255}};  // normalized: 0 .. 1
// quad.bin: positions and normals (2 x 48 bytes), TEXCOORD_0 (32), TEXCOORD_1 (4 x 2 bytes, stride 4), indices (12).
constexpr size_t kBinBytes = 156;

// A unit quad in z = 0 (mesh 0, two primitives over the same accessors: material 0, then none) with TEXCOORD_0 (float)
// and TEXCOORD_1 (normalized UNSIGNED_BYTE); materials: 0 MASK textured (texture 0, image 0), 1 BLEND untextured,
// 2 OPAQUE textured with image 1 (a file that does not exist: never decoded).
class GltfAlpha : public ::testing::Test {
 protected:
  GltfAlpha() {
    std::vector<unsigned char> bin;
    const auto put = [&](const void* data, size_t size) {
      bin.insert(bin.end(), static_cast<const unsigned char*>(data), static_cast<const unsigned char*>(data) + size);
    };
    const float positions[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, normals[] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    put(positions, 48), put(normals, 48), put(kUv0.data(), 32);
    for (const glm::u8vec2& t : kUv1) put(&t, 2), put("\0\0", 2);  // stride 4
    const uint16_t indices[] = {0, 1, 2, 0, 2, 3};
    put(indices, 12);
    std::ofstream(dir_ / "quad.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
    const std::vector<unsigned char> image = png(4, 2, 4, kAlphas);
    std::ofstream(dir_ / "holes.png", std::ios::binary)
        .write(reinterpret_cast<const char*>(image.data()), static_cast<std::streamsize>(image.size()));
    const Json primitive = {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}, {"TEXCOORD_1", 3}}},
                            {"indices", 4}};
    Json second = primitive;
    doc_ = {{"asset", {{"version", "2.0"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", {0}}}}},
            {"nodes", {{{"mesh", 0}}}},
            {"meshes", {{{"primitives", {primitive, second}}}}},
            {"buffers", {{{"uri", "quad.bin"}, {"byteLength", kBinBytes}}}},
            {"bufferViews",
             {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 96}, {"byteStride", 12}},
              {{"buffer", 0}, {"byteOffset", 96}, {"byteLength", 32}},
              {{"buffer", 0}, {"byteOffset", 128}, {"byteLength", 16}, {"byteStride", 4}},
              {{"buffer", 0}, {"byteOffset", 144}, {"byteLength", 12}}}},
            {"accessors",
             {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {0, 0, 0}},
               {"max", {1, 1, 0}}},
              {{"bufferView", 0}, {"byteOffset", 48}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
              {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
              {{"bufferView", 2}, {"componentType", 5121}, {"normalized", true}, {"count", 4}, {"type", "VEC2"}},
              {{"bufferView", 3}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
            {"materials",
             {{{"name", "holes"},
               {"alphaMode", "MASK"},
               {"alphaCutoff", 0.3},
               {"doubleSided", true},
               {"pbrMetallicRoughness",
                {{"baseColorFactor", {1, 1, 1, 0.9}},
                 {"baseColorTexture",
                  {{"index", 0},
                   {"texCoord", 1},
                   {"extensions",
                    {{"KHR_texture_transform",
                      {{"offset", {0.25, 0.5}}, {"rotation", 0.5}, {"scale", {2, 3}}, {"texCoord", 0}}}}}}}}}},
              {{"alphaMode", "BLEND"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.2}}}}},
              {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 1}}}}}}}},
            {"textures", {{{"source", 0}, {"sampler", 0}}, {{"source", 1}}}},
            {"images", {{{"uri", "holes.png"}}, {{"uri", "not-there.png"}}}},
            {"samplers", {{{"magFilter", 9728}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33648}}}}};
    doc_["meshes"][0]["primitives"][0]["material"] = 0;
  }
  std::string write(const Json& doc, const std::string& name = "quad.gltf") {
    std::ofstream(dir_ / name) << doc.dump();
    return (dir_ / name).string();
  }
  test::TempDir scratch_{"penumbra_gltf_alpha_test"};
  const fs::path dir_ = scratch_.path();
  Json doc_;
};

TEST_F(GltfAlpha, MaterialsTexturesAndCoordinatesAreRead) {
  const Scene s = loadGltf(write(doc_));
  ASSERT_EQ(s.triangleCount(), 4u);
  ASSERT_EQ(s.materials.size(), 4u);  // the file's three and glTF's default material (primitive 1 has none)
  EXPECT_EQ(s.materialIds, (std::vector<uint32_t>{0, 0, 3, 3}));
  const Material& m = s.materials[0];
  EXPECT_EQ(m.name, "holes");
  EXPECT_EQ(m.alphaMode, AlphaMode::kMask);
  EXPECT_FLOAT_EQ(m.alphaCutoff, 0.3f);
  EXPECT_FLOAT_EQ(m.baseAlpha, 0.9f);
  EXPECT_TRUE(m.doubleSided);
  EXPECT_EQ(m.texCoord, 0);  // KHR_texture_transform's texCoord overrides the textureInfo's 1
  EXPECT_EQ(m.uvTransform.offset, glm::vec2(0.25f, 0.5f));
  EXPECT_FLOAT_EQ(m.uvTransform.rotation, 0.5f);
  EXPECT_EQ(m.uvTransform.scale, glm::vec2(2, 3));
  EXPECT_EQ(m.wrapS, ALPHA_WRAP_CLAMP);
  EXPECT_EQ(m.wrapT, ALPHA_WRAP_MIRROR);
  EXPECT_EQ(m.filter, ALPHA_FILTER_NEAREST);  // magFilter NEAREST wins over minFilter LINEAR_MIPMAP_LINEAR
  ASSERT_EQ(m.alphaTexture, 0);
  ASSERT_EQ(s.alphaTextures.size(), 1u);  // image 1 (opaque material's, a missing file) was never read
  EXPECT_EQ(s.alphaTextures[0].width, 4u);
  EXPECT_EQ(s.alphaTextures[0].height, 2u);
  EXPECT_EQ(s.alphaTexels, kAlphas);
  EXPECT_NE(s.alphaTextures[0].name.find("holes.png"), std::string::npos);
  EXPECT_EQ(s.materials[1].alphaMode, AlphaMode::kBlend);
  EXPECT_FLOAT_EQ(s.materials[1].alphaCutoff, 0.5f);  // BLEND is drawn as MASK at 0.5
  EXPECT_TRUE(s.materials[1].mayDiscard());  // 0.2 < 0.5: discards everywhere
  EXPECT_EQ(s.materials[2].alphaTexture, -1);
  EXPECT_FALSE(s.materials[3].doubleSided);  // glTF's default material is single-sided
  ASSERT_EQ(s.uvs.size(), s.positions.size());
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(s.uvs[i], kUv0[i]);  // primitive 0 reads TEXCOORD_0
  EXPECT_NE(describeMaterials(s).find("1 MASK, 0 BLEND as MASK"), std::string::npos) << describeMaterials(s);
}

TEST_F(GltfAlpha, NormalizedTexCoordsBlendCutoffAndImagesWithoutAlpha) {
  doc_["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = Json::object();
  doc_["meshes"][0]["primitives"][0]["material"] = 0;
  doc_["meshes"][0]["primitives"][1]["material"] = 1;
  LoadOptions options;
  options.blendCutoff = 0.125f;
  const Scene s = loadGltf(write(doc_), options);
  EXPECT_EQ(s.materials[0].texCoord, 1);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(s.uvs[i], glm::vec2(kUv1[i]) / 255.0f);
  EXPECT_FLOAT_EQ(s.materials[1].alphaCutoff, 0.125f);
  EXPECT_FALSE(s.materials[1].mayDiscard());  // factor 0.2 >= 0.125: nothing is discarded
  // An RGB image has no alpha: the material's alpha is its factor alone, nothing is kept.
  const std::vector<unsigned char> rgb = png(4, 2, 3, {});
  std::ofstream(dir_ / "holes.png", std::ios::binary)
      .write(reinterpret_cast<const char*>(rgb.data()), static_cast<std::streamsize>(rgb.size()));
  const Scene plain = loadGltf(write(doc_, "rgb.gltf"));
  EXPECT_EQ(plain.materials[0].alphaTexture, -1);
  EXPECT_TRUE(plain.alphaTexels.empty());
  EXPECT_FALSE(plain.materials[0].mayDiscard());  // 0.9 >= 0.3
}

TEST_F(GltfAlpha, DataUriAndGlbBufferViewImages) {
  doc_["images"][0] = {{"uri", "data:image/png;base64," + base64(png(4, 2, 4, kAlphas))}};
  const Scene uri = loadGltf(write(doc_, "uri.gltf"));
  EXPECT_EQ(uri.alphaTexels, kAlphas);
  // A GLB whose BIN chunk holds the geometry and the PNG.
  std::vector<unsigned char> bin(kBinBytes);
  std::ifstream(dir_ / "quad.bin", std::ios::binary).read(reinterpret_cast<char*>(bin.data()), kBinBytes);
  const std::vector<unsigned char> image = png(4, 2, 4, kAlphas);
  bin.insert(bin.end(), image.begin(), image.end());
  while (bin.size() % 4 != 0) bin.push_back(0);
  Json doc = doc_;
  doc["buffers"] = {{{"byteLength", bin.size()}}};
  doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", kBinBytes}, {"byteLength", image.size()}});
  doc["images"][0] = {{"bufferView", 4}, {"mimeType", "image/png"}};
  std::string json = doc.dump();
  while (json.size() % 4 != 0) json += ' ';
  std::vector<unsigned char> glb = {'g', 'l', 'T', 'F', 2, 0, 0, 0, 0, 0, 0, 0};
  const auto u32 = [&](uint32_t v) {
    for (int k = 0; k < 4; ++k) glb.push_back(static_cast<unsigned char>(v >> (8 * k)));
  };
  u32(static_cast<uint32_t>(json.size())), u32(0x4E4F534A);
  glb.insert(glb.end(), json.begin(), json.end());
  u32(static_cast<uint32_t>(bin.size())), u32(0x004E4942);
  glb.insert(glb.end(), bin.begin(), bin.end());
  const uint32_t length = static_cast<uint32_t>(glb.size());
  std::memcpy(glb.data() + 8, &length, 4);
  std::ofstream(dir_ / "quad.glb", std::ios::binary)
      .write(reinterpret_cast<const char*>(glb.data()), static_cast<std::streamsize>(glb.size()));
  const Scene packed = loadGltf((dir_ / "quad.glb").string());
  EXPECT_EQ(packed.alphaTexels, kAlphas);
  // A PNG declared as a JPEG (sec. 5.18) is decoded as what it is, with a warning.
  doc_["images"][0] = {{"uri", "data:image/jpeg;base64," + base64(png(4, 2, 4, kAlphas))}, {"mimeType", "image/jpeg"}};
  test::CapturingOptions capture;
  EXPECT_EQ(loadGltf(write(doc_), capture.options).alphaTexels, kAlphas);
  ASSERT_EQ(capture.warnings.size(), 1u);
  EXPECT_NE(capture.warnings[0].find("image 0: declared image/jpeg but its bytes are PNG"), std::string::npos)
      << capture.warnings[0];
}

TEST_F(GltfAlpha, TextureBudgetIsEnforced) {
  LoadOptions options;
  options.maxTextureBytes = 7;  // the texture has 8 alpha texels
  EXPECT_TRUE(throwsWith([&] { loadGltf(write(doc_), options); },
                         {"quad.gltf", "image 0 \"holes.png\"", "limit of 7 bytes"}));
}

// Each malformed variant of the quad: one SceneError naming the file and the element.
TEST_F(GltfAlpha, MalformedInputGivesOneClearError) {
  struct Case {
    const char* what;
    Json patch;  // JSON merge patch on the document
    std::vector<std::string> parts;
  };
  const std::vector<Case> cases = {
      {"missing image file",
       {{"images", {{{"uri", "gone.png"}}, {{"uri", "x.png"}}}}},
       {"image 0 \"gone.png\"", "file not found"}},
      {"image outside the folder",
       {{"images", {{{"uri", "../holes.png"}}, {{"uri", "x.png"}}}}},
       {"image 0 \"../holes.png\"", "its \"..\" components leave the scene's folder"}},
      {"undecodable image",
       {{"images", {{{"uri", "quad.bin"}}, {{"uri", "x.png"}}}}},
       {"image 0 \"quad.bin\"", "not a PNG, JPEG, BMP or GIF image (its first bytes: "}},
      {"truncated PNG",
       {{"images", {{{"uri", "truncated.png"}}, {{"uri", "x.png"}}}}},
       {"image 0 \"truncated.png\"", "a PNG of 40 bytes that cannot be decoded ("}},
      {"PNG past the decoder's size",
       {{"images", {{{"uri", "huge.png"}}, {{"uri", "x.png"}}}}},
       {"image 0 \"huge.png\"", "a PNG of 33554432x2 pixels: more than the decoder's 16777216 pixels a side"}},
      {"texCoord set missing",
       {{"materials",
         {{{"alphaMode", "MASK"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 2}}}}}}}}},
       {"mesh 0 primitive 0", "reads TEXCOORD_2, which the primitive does not have"}},
      {"texture index out of range",
       {{"materials", {{{"alphaMode", "MASK"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 5}}}}}}}}},
       {"/materials/0/pbrMetallicRoughness/baseColorTexture/index", "no element 5 in textures"}},
      {"unknown alphaMode", {{"materials", {{{"alphaMode", "CUTOUT"}}}}}, {"/materials/0/alphaMode", "\"MASK\""}},
      {"negative cutoff", {{"materials", {{{"alphaCutoff", -1}}}}}, {"/materials/0/alphaCutoff", ">= 0"}},
      {"bad wrap mode", {{"samplers", {{{"wrapS", 1234}}}}}, {"/samplers/0/wrapS", "33071"}},
      {"bad transform",
       {{"materials",
         {{{"alphaMode", "MASK"},
           {"pbrMetallicRoughness",
            {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {1}}}}}}}}}}}}}},
       {"KHR_texture_transform/scale", "2 numbers"}},
  };
  std::vector<unsigned char> image = png(4, 2, 4, kAlphas);
  std::ofstream(dir_ / "truncated.png", std::ios::binary).write(reinterpret_cast<const char*>(image.data()), 40);
  image[16] = 2, image[17] = image[18] = image[19] = 0;  // IHDR width 2^25 (its CRC no longer matters)
  std::ofstream(dir_ / "huge.png", std::ios::binary)
      .write(reinterpret_cast<const char*>(image.data()), static_cast<std::streamsize>(image.size()));
  for (const Case& c : cases) {
    Json doc = doc_;
    doc.merge_patch(c.patch);
    std::vector<std::string> parts = c.parts;
    parts.push_back("bad.gltf");
    EXPECT_TRUE(throwsWith([&] { loadGltf(write(doc, "bad.gltf")); }, parts)) << c.what;
  }
}

}  // namespace scene_gltf_alpha_test
}  // namespace penumbra
