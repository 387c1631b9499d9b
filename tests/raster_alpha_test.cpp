// Alpha-tested triangles in the binned rasterizer (raster/alpha.h, the fine stage's alpha test): soups of masked and
// opaque triangles against the reference rasterizer (exact coverage; alpha decided in double, pixels whose alpha lies
// within kAlphaBorder of the cutoff left to either side), near-plane and guard-band clipping of masked triangles, a
// card with a square hole whose shadow map has no depth in the hole, the camera G-buffer seeing through it and
// culling single-sided back faces, and opaque scenes drawn bit for bit as without materials.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "host/views/raster_scene.h"
#include "raster/rasterizer.h"
#include "tests/raster_support.h"
#include "tests/support/cl_test.h"
#include "tools/selftest/reference/raster_ref.h"

namespace penumbra::test {
namespace raster_alpha_test {

class RasterAlpha : public ClTest {};

class RasterAlphaSoup : public ClTestWithParam<MaskedCase> {};

TEST_P(RasterAlphaSoup, MatchesReference) {
  const MaskedCase& c = GetParam();
  const Scene scene = maskedSoup(300, 77, c.filter);
  const RasterView view = maskedView(c);
  Rasterizer raster(ctx());
  uploadScene(raster, scene);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  const RefRasterizer ref(scene, view);
  const RasterComparison cmp = compareWithReference(out, ref, view, 10.0);
  const size_t border = borderPixels(ref);
  EXPECT_TRUE(matchesReference(cmp, soupTiesAllowed(cmp.covered) + border));
  // The masks matter: the reference without them differs in many pixels.
  Scene opaque = scene;
  opaque.materials.clear(), opaque.materialIds.clear();
  size_t differ = 0;
  const RefRaster& masked = ref.result();
  const RefRasterizer plain(opaque, view);
  for (size_t i = 0; i < masked.triangleId.size(); ++i) differ += masked.triangleId[i] != plain.result().triangleId[i];
  EXPECT_GT(differ, cmp.covered / 10);
  RecordProperty("alpha_border_pixels", static_cast<int>(border));
}

std::string maskedName(const ::testing::TestParamInfo<MaskedCase>& info) { return info.param.name(); }

INSTANTIATE_TEST_SUITE_P(Masked, RasterAlphaSoup, ::testing::ValuesIn(maskedCases()), maskedName);

// A masked ground reaching far behind the eye: its near-plane fans (clipped records whose vertices are not the
// triangle's own) still sample at the right texture coordinates.
TEST_F(RasterAlpha, ClippedMaskedTrianglesMatchReference) {
  Scene s = makeScene({{-400, -1, -400}, {400, -1, -400}, {400, -1, 400}, {-400, -1, 400}}, {{0, 2, 1}, {0, 3, 2}});
  s.materials = {plainMaterial()};
  addMaskMaterial(s, 8, ALPHA_FILTER_NEAREST, ALPHA_WRAP_REPEAT, 5);
  s.materialIds = {1, 1};
  s.uvs = {{0, 0}, {200, 0}, {200, 200}, {0, 200}};  // one texture repeat per 4 world units
  const RasterView view = perspectiveView(128, 96, {0.3f, 0.5f, 2.0f}, {0, -1, -3}, 70.0f, 0.05f, 100.0f);
  Rasterizer raster(ctx());
  uploadScene(raster, s);
  const RasterOutput out = drawPoisoned(ctx(), raster, view);
  const RefRasterizer ref(s, view);
  EXPECT_GT(ref.fannedTriangles(), 0u);
  const RasterComparison cmp = compareWithReference(out, ref, view, 100.0);
  EXPECT_TRUE(matchesReference(cmp, cmp.covered / 200 + 2 + borderPixels(ref)));
  EXPECT_GT(cmp.covered, 3000u);
}

// A 2x2 card at z = 0 facing +z whose 16x16 texture has a square hole over texels [4, 12)^2 (u, v in [0.25, 0.75)),
// in front of an opaque background plane at z = -1; `card` is triangles 0 and 1.
Scene holedCard(int filter, bool doubleSided) {
  Scene s = makeScene({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {-3, -3, -1}, {3, -3, -1}, {3, 3, -1}, {-3, 3, -1}},
                      {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}});
  s.materials = {plainMaterial()};
  Material m;
  m.name = "holed";
  m.alphaMode = AlphaMode::kMask;
  m.alphaTexture = 0;
  m.filter = filter;
  m.doubleSided = doubleSided;
  s.materials.push_back(m);
  s.alphaTextures.push_back({"hole", 16, 16, 0});
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) s.alphaTexels.push_back(x >= 4 && x < 12 && y >= 4 && y < 12 ? 0 : 255);
  s.materialIds = {1, 1, 0, 0};
  // u along +x, v along -y (v = 0 at the card's top edge, as images have it).
  s.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}};
  return s;
}

// The map of the holed card seen straight on from +z (orthographic 4x4 window, 64x64 texels: 16 texels per card
// unit), and under a perspective spot view: every texel whose centre lies more than one texel inside the hole shows
// the background, every one more than one texel inside the card's solid frame shows the card.
TEST_F(RasterAlpha, ShadowMapHasNoDepthInTheHole) {
  for (int filter : {ALPHA_FILTER_NEAREST, ALPHA_FILTER_LINEAR})
    for (bool perspective : {false, true}) {
      const Scene scene = holedCard(filter, true);
      const RasterView view =
          perspective ? perspectiveView(64, 64, {0, 0, 4}, {0, 0, 0}, 53.13010235f, 1.0f, 10.0f)  // 4x4 at z = 0
                      : orthoView(64, 64, {0, 0, 4}, {0, 0, 0}, {-2, 2, -2, 2}, 1.0f, 10.0f);
      Rasterizer raster(ctx());
      uploadScene(raster, scene);
      const RasterOutput out = drawPoisoned(ctx(), raster, view);
      const float texel = 4.0f / 64;  // card units per map texel at z = 0 (both views)
      int hole = 0, frame = 0;
      for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
          const float px = -2 + (x + 0.5f) * texel, py = -2 + (y + 0.5f) * texel;  // on the card's plane
          const float inHole = 0.5f - std::max(std::abs(px), std::abs(py));      // > 0 inside the hole
          const float inCard = 1.0f - std::max(std::abs(px), std::abs(py));      // > 0 on the card
          const uint32_t id = out.ids[static_cast<size_t>(y) * 64 + x];
          if (inHole > texel) {
            ++hole;
            EXPECT_GE(id, 2u) << x << "," << y << " sees the card through its hole";
            EXPECT_NEAR(out.depth[static_cast<size_t>(y) * 64 + x], 5.0f, 1e-4f);  // the background's view depth
          } else if (inHole < -texel && inCard > texel) {
            ++frame;
            EXPECT_LT(id, 2u) << x << "," << y << " misses the card's frame";
          }
        }
      EXPECT_GT(hole, 150);
      EXPECT_GT(frame, 500);
    }
}

// The camera G-buffer culls the back faces of single-sided materials (RasterView::cullSingleSided) and sees the
// background through the hole; a shadow-map draw of the same view keeps both sides.
TEST_F(RasterAlpha, SingleSidedBackFacesAreCulledOnlyWhereTheViewAsks) {
  struct Sides {
    bool card, background;  // doubleSided
  };
  // Seen from -z both face away. Mixed sidedness reads per-triangle bits; all single-sided culls every back face.
  for (const Sides sides : {Sides{false, true}, Sides{true, false}, Sides{false, false}}) {
    Scene scene = holedCard(ALPHA_FILTER_NEAREST, sides.card);
    scene.materials[0].doubleSided = sides.background;
    RasterView view = orthoView(64, 64, {0, 0, -4}, {0, 0, 0}, {-2, 2, -2, 2}, 1.0f, 10.0f);
    view.cullSingleSided = true;
    Rasterizer raster(ctx());
    uploadScene(raster, scene);
    GBuffer g;
    raster.drawGBuffer(view, g);
    const std::vector<uint32_t> seen = g.triangleId.download(ctx());
    RasterView shadow = view;
    shadow.cullSingleSided = false;
    const RasterOutput map = drawPoisoned(ctx(), raster, shadow);
    // Pixel (20, 32) lies on the card's frame (world x = 0.72: the view looks along +z, so x is mirrored), (32, 32)
    // in its hole; the background (z = -1) is in front of the card (z = 0) from here.
    const size_t frame = 32 * 64 + 20, hole = 32 * 64 + 32;
    EXPECT_EQ(seen[frame] >= 2 && seen[frame] != kNoTriangle, sides.background) << sides.card << sides.background;
    EXPECT_EQ(seen[hole] >= 2 && seen[hole] != kNoTriangle, sides.background) << sides.card << sides.background;
    if (!sides.background) {  // culled: the frame shows a double-sided card's back, or nothing; the hole nothing
      EXPECT_EQ(seen[hole], kNoTriangle);
      EXPECT_EQ(seen[frame] < 2, sides.card);
      EXPECT_EQ(seen[frame] == kNoTriangle, !sides.card);
    }
    EXPECT_GE(map.ids[frame], 2u);  // the shadow-map draw keeps both sides: the background is nearest
    const RefRasterizer ref(scene, view);
    EXPECT_EQ(ref.result().triangleId[frame], seen[frame]);
    EXPECT_EQ(ref.result().triangleId[hole], seen[hole]);
  }
}

// Materials that cannot discard change nothing: the soup with an opaque double-sided material and one masked
// triangle outside the view (so setup reads per-triangle bits) draws every depth and id bit for bit as without
// materials.
TEST_F(RasterAlpha, OpaqueTrianglesAreDrawnBitForBitAsWithoutMaterials) {
  const Scene plain = triangleSoup(400, 99, 1.8f, 0.6f);
  Scene withMaterials = plain;
  withMaterials.positions.insert(withMaterials.positions.end(), {{50, 50, 50}, {51, 50, 50}, {50, 51, 50}});
  withMaterials.normals.resize(withMaterials.positions.size(), glm::vec3(0, 0, 1));
  const uint32_t n = static_cast<uint32_t>(plain.positions.size());
  withMaterials.triangles.push_back({n, n + 1, n + 2});
  withMaterials.objectIds.push_back(0);
  withMaterials.materials = {plainMaterial()};
  addMaskMaterial(withMaterials, 4, ALPHA_FILTER_LINEAR, ALPHA_WRAP_REPEAT, 3);
  withMaterials.materialIds.assign(withMaterials.triangles.size(), 0);
  withMaterials.materialIds.back() = 1;
  withMaterials.uvs.assign(withMaterials.positions.size(), glm::vec2(0.5f));
  for (bool ortho : {false, true}) {
    const RasterView view = ortho ? orthoView(131, 67, {0.5f, 1, 6}, {0, 0, 0}, {-2.2f, 2, -1.9f, 2.1f}, 1, 11)
                                  : perspectiveView(131, 67, {0.5f, 1, 6}, {0, 0, 0}, 50, 0.5f, 20);
    Rasterizer a(ctx()), b(ctx());
    uploadScene(a, plain);
    uploadScene(b, withMaterials);
    const RasterOutput x = drawPoisoned(ctx(), a, view), y = drawPoisoned(ctx(), b, view);
    EXPECT_EQ(x.ids, y.ids);
    EXPECT_EQ(0, std::memcmp(x.depth.data(), y.depth.data(), x.depth.size() * sizeof(float)));
  }
}

}  // namespace raster_alpha_test
}  // namespace penumbra::test
