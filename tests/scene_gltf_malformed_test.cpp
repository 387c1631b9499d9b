// glTF files broken in one way each (tests/data/scenes/malformed/, written by make_test_files.py) must be
// refused with a SceneError naming the file and the element; plus cases built at run time: symlinks out
// of the folder, directories, size limits, empty and garbage files.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "host/scene/gltf_loader.h"
#include "scene_test_util.h"
#include "tests/support/temp_dir.h"

namespace penumbra {
namespace scene_gltf_malformed_test {

namespace fs = std::filesystem;
using test::sceneData;
using test::throwsWith;

struct Broken {
  const char* file;
  std::vector<std::string> parts;  // the message must contain each
};

class GltfMalformed : public ::testing::TestWithParam<Broken> {};

TEST_P(GltfMalformed, IsRefusedWithAClearMessage) {
  const std::string path = sceneData(GetParam().file);
  std::vector<std::string> parts = GetParam().parts;
  parts.push_back(path);  // every message names the file
  EXPECT_TRUE(throwsWith([&] { loadGltf(path); }, parts));
}

INSTANTIATE_TEST_SUITE_P(
    Gltf, GltfMalformed,
    ::testing::Values(
        Broken{"malformed/truncated.glb", {"GLB", "header says 752 bytes but the file has 376"}},
        Broken{"malformed/header_only.glb", {"GLB", "the file has 12"}},
        Broken{"malformed/bad_json_chunk_length.glb", {"chunk 0", "runs past the end"}},
        Broken{"malformed/bad_bin_chunk_length.glb", {"chunk 1", "runs past the end"}},
        Broken{"malformed/bin_not_aligned.glb", {"chunk 1", "not a multiple of 4"}},
        Broken{"malformed/wrong_version.glb", {"container version 1"}}, Broken{"malformed/no_bin_chunk.glb", {"BIN"}},
        Broken{"malformed/traversal.gltf",
               {"buffer \"../triangle.bin\"", "its \"..\" components leave the scene's folder"}},
        Broken{"malformed/traversal_encoded.gltf", {"its \"..\" components leave the scene's folder"}},
        Broken{"sub/inner.gltf", {"its \"..\" components leave the scene's folder"}},
        Broken{"malformed/absolute_uri.gltf", {"/etc/passwd", "absolute paths are not allowed"}},
        Broken{"malformed/nul_uri.gltf", {"buffer \"tri\\0angle.bin\": path contains a NUL byte"}},
        Broken{"malformed/file_uri.gltf", {"URI schemes"}},
        Broken{"malformed/missing_bin.gltf", {"nowhere.bin", "file not found"}},
        Broken{"malformed/count_overflow.gltf", {"/accessors/0/count", "18446744073709551615 is larger"}},
        Broken{"malformed/index_out_of_range.gltf", {"accessor 2: index 16256 out of range (vertex count 3)"}},
        Broken{"malformed/node_cycle.gltf", {"cycle", "node 1 -> node 2 -> node 3 -> node 1"}},
        Broken{"malformed/two_parents.gltf", {"node 2: has two parents (node 0 and node 1)"}},
        Broken{"malformed/draco_required.gltf", {"KHR_draco_mesh_compression is required but not supported"}},
        Broken{"malformed/meshopt_required.gltf", {"EXT_meshopt_compression is required but not supported"}},
        Broken{"malformed/nan_matrix.gltf", {"invalid JSON", "1e999"}},
        Broken{"malformed/nan_token.gltf", {"invalid JSON"}},
        Broken{"malformed/non_affine_matrix.gltf", {"node 0: matrix is not affine"}},
        Broken{"malformed/matrix_length.gltf", {"/nodes/0/matrix", "16 numbers"}},
        Broken{"malformed/world_overflow.gltf", {"node 1: world transform overflows"}},
        Broken{"malformed/missing_position.gltf", {"mesh 0 primitive 0: missing required attribute POSITION"}},
        Broken{"malformed/position_type.gltf", {"accessor 0: POSITION must be VEC3 of FLOAT", "UNSIGNED_SHORT"}},
        Broken{"malformed/index_type.gltf", {"accessor 2: indices must be SCALAR", "FLOAT"}},
        Broken{"malformed/view_past_buffer.gltf", {"bufferView 1", "past the end of buffer 0 (80 bytes)"}},
        Broken{"malformed/accessor_past_view.gltf", {"accessor 0", "need 84 bytes, bufferView 0 has 72"}},
        Broken{"malformed/stride_too_small.gltf", {"accessor 0: byteStride 8"}},
        Broken{"malformed/bad_mode.gltf", {"/meshes/0/primitives/0/mode"}},
        Broken{"malformed/bad_scene.gltf", {"/scene", "no element 3 in scenes"}},
        Broken{"malformed/nodes_not_array.gltf", {"/nodes: expected an array, got \"all\""}},
        Broken{"malformed/normal_count.gltf", {"NORMAL has 2 elements but POSITION has 3"}}),
    [](const auto& test_info) {
      std::string name = fs::path(test_info.param.file).stem().string();
      for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
      return name;
    });

// A fresh folder per test, removed afterwards; files are written into it at run time.
class GltfRuntime : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return (dir_ / name).string();
  }
  std::string copyTriangle(const std::string& binName) {
    std::ifstream in(sceneData("triangle.gltf"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find("triangle.bin"), 12, binName);
    return write("scene.gltf", text);
  }
  test::TempDir scratch_{"penumbra_scene_test"};  // removed with the fixture
  const fs::path dir_ = scratch_.path();
};

TEST_F(GltfRuntime, SymlinkOutOfTheFolderIsRefused) {
  fs::create_symlink(sceneData("triangle.bin"), dir_ / "link.bin");
  EXPECT_TRUE(throwsWith([&] { loadGltf(copyTriangle("link.bin")); }, {"link.bin", "outside the scene's folder"}));
}

TEST_F(GltfRuntime, SymlinkInsideTheFolderIsFine) {
  fs::copy_file(sceneData("triangle.bin"), dir_ / "real.bin");
  fs::create_symlink(dir_ / "real.bin", dir_ / "link.bin");
  EXPECT_EQ(loadGltf(copyTriangle("link.bin")).triangleCount(), 1u);
}

TEST_F(GltfRuntime, DirectoryAsBufferIsRefused) {
  fs::create_directories(dir_ / "folder.bin");
  EXPECT_TRUE(throwsWith([&] { loadGltf(copyTriangle("folder.bin")); }, {"not a regular file"}));
}

TEST_F(GltfRuntime, FileSizeLimits) {
  fs::copy_file(sceneData("triangle.bin"), dir_ / "triangle.bin");
  const std::string path = copyTriangle("triangle.bin");
  LoadOptions small;
  small.maxFileBytes = 100;  // the .gltf is about 1 kB, the .bin 80 bytes
  EXPECT_TRUE(throwsWith([&] { loadGltf(path, small); }, {"over the limit of 100 bytes"}));
  LoadOptions total;
  total.maxTotalBytes = 1050;  // the .gltf (1013 bytes) fits, the .gltf and .bin together do not
  EXPECT_TRUE(throwsWith([&] { loadGltf(path, total); }, {"triangle.bin", "limit on bytes read per load"}));
}

TEST_F(GltfRuntime, TriangleLimit) {
  LoadOptions options;
  options.maxTriangles = 1000;
  EXPECT_TRUE(throwsWith([&] { loadGltf(test::bundledScene("Suzanne.glb"), options); }, {"limit"}));
}

TEST_F(GltfRuntime, JsonValueLimit) {
  LoadOptions options;
  options.maxJsonValues = 10;  // triangle.gltf has about 60
  EXPECT_TRUE(throwsWith([&] { loadGltf(sceneData("triangle.gltf"), options); }, {"more than 10 JSON values"}));
}

// tinygltf's DOM and its struct per element are estimated before either is built: 50,000 bare accessors (2.5 MB of
// text, ~40 MB once parsed) pass the default budget and are refused by a smaller one, naming the array; the
// Suzanne.glb the README renders passes a budget of 1 MiB.
// Where the Khronos validator and the specification disagreed with the loader (docs/robustness.md, "Loader
// verdicts"): each case decided by the specification.
TEST_F(GltfRuntime, SpecificationVerdictsAgreeWithTheValidator) {
  std::ifstream in(sceneData("triangle.gltf"));
  const nlohmann::json triangle = nlohmann::json::parse(in);
  fs::copy_file(sceneData("triangle.bin"), dir_ / "triangle.bin");
  const auto load = [&](const nlohmann::json& doc, const std::string& name, std::vector<std::string>* warnings) {
    const std::string path = write(name, doc.dump());
    test::CapturingOptions capture;
    Scene scene = loadGltf(path, capture.options);
    if (warnings) *warnings = capture.warnings;
    return scene;
  };
  struct Bad {
    const char* what;
    nlohmann::json patch;
    std::string message;
  };
  for (const Bad& bad : std::vector<Bad>{
           {"byteStride 0",
            {{"bufferViews", {{{"buffer", 0}, {"byteLength", 72}, {"byteStride", 0}}, triangle["bufferViews"][1]}}},
            "/bufferViews/0/byteStride: 0 is not a multiple of 4 in 4..252"},
           {"minVersion above version",
            {{"asset", {{"version", "2.0"}, {"minVersion", "2.1"}}}},
            "/asset/minVersion: 2.1 is above version 2.0"},
           {"minVersion beyond 2.0",
            {{"asset", {{"version", "2.1"}, {"minVersion", "2.1"}}}},
            "/asset/minVersion: the asset needs glTF 2.1; this loader reads 2.0"},
           {"data URI of another media type",
            {{"buffers", {{{"byteLength", 80}, {"uri", "data:text/plain;base64,AAAA"}}}}},
            "/buffers/0/uri: a buffer's data URI starts \"data:application/octet-stream;base64,\""},
           {"data URI with a bad character",
            {{"buffers", {{{"byteLength", 3}, {"uri", "data:application/octet-stream;base64,AA@A"}}}}},
            "/buffers/0/uri: its base64 holds @ at character 2"},
           {"data URI shorter than the buffer",
            {{"buffers", {{{"byteLength", 80}, {"uri", "data:application/octet-stream;base64,AAAA"}}}}},
            "/buffers/0/uri: its base64 decodes to 3 bytes, fewer than the buffer's byteLength 80"},
           {"negative light intensity",
            {{"extensions", {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", -1}}}}}}}}},
            "/extensions/KHR_lights_punctual/lights/0/intensity: expected a finite number >= 0"},
       }) {
    nlohmann::json doc = triangle;
    doc.merge_patch(bad.patch);
    EXPECT_TRUE(throwsWith([&] { load(doc, "bad.gltf", nullptr); }, {bad.message})) << bad.what;
  }
  // A ".." that stays inside the folder is a legal URI.
  fs::create_directories(dir_ / "sub");
  nlohmann::json inside = triangle;
  inside["buffers"][0]["uri"] = "sub/../triangle.bin";
  EXPECT_EQ(load(inside, "inside.gltf", nullptr).triangleCount(), 1u);

  // GLB: trailing bytes after the header's length are ignored with a warning; a JSON chunk with a byte-order mark or
  // padded with NULs instead of spaces is refused.
  const auto glb = [&](std::string json, const std::string& name, size_t trailing) {
    std::ifstream binIn(dir_ / "triangle.bin", std::ios::binary);
    std::string bin((std::istreambuf_iterator<char>(binIn)), std::istreambuf_iterator<char>());
    const char pad = json.back() == '\0' ? '\0' : ' ';
    while (json.size() % 4) json += pad;
    std::string out = "glTF";
    const auto u32 = [&](uint32_t v) {
      for (int k = 0; k < 4; ++k) out += static_cast<char>(v >> (8 * k));
    };
    u32(2), u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    u32(static_cast<uint32_t>(json.size())), u32(0x4E4F534A);
    out += json;
    u32(static_cast<uint32_t>(bin.size())), u32(0x004E4942);
    out += bin + std::string(trailing, 'x');
    return write(name, out);
  };
  nlohmann::json packed = triangle;
  packed["buffers"][0].erase("uri");
  test::CapturingOptions capture;
  EXPECT_EQ(loadGltf(glb(packed.dump(), "trailing.glb", 8), capture.options).triangleCount(), 1u);
  ASSERT_EQ(capture.warnings.size(), 1u);
  EXPECT_NE(capture.warnings[0].find("GLB: 8 bytes after the container's"), std::string::npos) << capture.warnings[0];
  EXPECT_TRUE(throwsWith([&] { loadGltf(glb("\xef\xbb\xbf" + packed.dump(), "bom.glb", 0)); },
                         {"bom.glb: GLB: the JSON chunk starts with a byte-order mark"}));
  std::string nul = packed.dump() + std::string(1, '\0');
  while (nul.size() % 4) nul += '\0';
  EXPECT_TRUE(throwsWith([&] { loadGltf(glb(nul, "nul.glb", 0)); },
                         {"nul.glb: GLB: the JSON chunk is padded with 0x00 bytes"}));
}

TEST_F(GltfRuntime, ParseBudgetIsCheckedBeforeTheDocumentIsBuilt) {
  std::string text = R"({"asset": {"version": "2.0"}, "accessors": [)";
  for (int i = 0; i < 50000; ++i)
    text += std::string(i ? "," : "") + R"({"componentType": 5126, "count": 1, "type": "VEC3"})";
  text += "]}";
  const fs::path path = dir_ / "accessors.gltf";
  std::ofstream(path) << text;
  EXPECT_TRUE(throwsWith([&] { loadGltf(path, {}); }, {"no triangles"}));
  LoadOptions options;
  options.maxParseBytes = 16 << 20;
  EXPECT_TRUE(throwsWith(
      [&] { loadGltf(path, options); },
      {"parsing it would hold more than 16 MiB", "elements of \"accessors\"", "LoadOptions::maxParseBytes"}));
  options.maxParseBytes = 1 << 20;
  EXPECT_NO_THROW(loadGltf(test::bundledScene("Suzanne.glb"), options));
}

TEST_F(GltfRuntime, CountTimesStrideOverflowIsCaught) {
  LoadOptions options;
  options.maxVertices = ~uint64_t{0};  // let the count through to the byte-range arithmetic
  // The schema pass refuses any glTF integer above INT32_MAX before the accessor's byte arithmetic sees it.
  EXPECT_TRUE(throwsWith([&] { loadGltf(sceneData("malformed/count_overflow.gltf"), options); },
                         {"/accessors/0/count: 18446744073709551615 is larger than 2147483647"}));
}

TEST_F(GltfRuntime, NormalizedFloatPositionsNameTheFlag) {
  fs::copy_file(sceneData("triangle.bin"), dir_ / "triangle.bin");
  std::ifstream in(sceneData("triangle.gltf"));
  nlohmann::json doc = nlohmann::json::parse(in);
  doc["accessors"][0]["normalized"] = true;  // FLOAT may not be normalized: the message must say what is wrong
  const std::string path = write("normalized.gltf", doc.dump());
  EXPECT_TRUE(throwsWith([&] { loadGltf(path); }, {"POSITION must be VEC3 of FLOAT, got VEC3 of normalized FLOAT"}));
}

TEST_F(GltfRuntime, EmptyGarbageAndMissingFiles) {
  EXPECT_TRUE(throwsWith([&] { loadGltf(write("empty.gltf", "")); }, {"empty.gltf", "invalid JSON"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(write("empty.glb", "")); }, {"empty.glb", "GLB"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(write("garbage.gltf", "{\"asset\": [")); }, {"garbage.gltf", "invalid JSON"}));
  EXPECT_TRUE(
      throwsWith([&] { loadGltf(write("array.gltf", "[1, 2]")); }, {"array.gltf", "expected a glTF JSON object"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(write("v1.gltf", "{\"asset\": {\"version\": \"1.0\"}}")); }, {"version 1.0"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(write("deep.gltf", std::string(100000, '[') + std::string(100000, ']'))); },
                         {"deep.gltf", "nested deeper than 64 levels"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf((dir_ / "missing.gltf").string()); }, {"missing.gltf", "file not found"}));
  EXPECT_TRUE(throwsWith([&] { loadGltf(dir_.string()); }, {"is a directory, not a scene file"}));
}

}  // namespace scene_gltf_malformed_test
}  // namespace penumbra
