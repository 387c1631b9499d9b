// Constants of the binned rasterizer, shared by the host and every raster/*.cl kernel (valid OpenCL C 1.2
// and C++20). Each states its unit or invariant. Layout: viewport -> bins of 16x16 tiles -> tiles of 8x8
// pixels (Laine & Karras, "High-Performance Software Rasterization on GPUs", HPG 2011, section 3).
#ifndef PENUMBRA_RASTER_CONSTANTS_H
#define PENUMBRA_RASTER_CONSTANTS_H

// ---- Fixed point -------------------------------------------------------------------------------------------
// Window coordinates are snapped to 1/256 pixel. A pixel (i, j) samples its centre at subpixel
// (256 i + 128, 256 j + 128); row 0 is the bottom row (y up, as NDC).
#define RASTER_SUBPIXEL_LOG2 8                        // subpixel bits per pixel
#define RASTER_SUBPIXELS (1 << RASTER_SUBPIXEL_LOG2)  // subpixels per pixel (256)
#define RASTER_SAMPLE_OFFSET (RASTER_SUBPIXELS / 2)   // pixel centre inside its pixel, subpixels
// Conservative draws (tile lists for exact tests, Rasterizer::drawTileLists) dilate every pixel rectangle by this many
// subpixels on each side: snapping moves a vertex by at most half a subpixel, so the exact projected triangle lies
// within 0.5 subpixel of the snapped one, and the rest absorbs the rounding of a point projected in float elsewhere
// (below 0.5 subpixel at 8192 pixels).
#define RASTER_CONSERVATIVE_DILATION 32
// Guard band: triangles are clipped in homogeneous clip space to |x_c| <= G w_c (same for y) with the power of
// two G = 2^RASTER_GUARD_LOG2 / 2^ceil(log2(size)), i.e. 2^19 .. 2^20 pixels beyond each side of the viewport
// (a power of two, so G w_c is exact and the clip tests cannot depend on fused multiply-adds).
#define RASTER_GUARD_LOG2 21  // G * size <= 2^21 NDC units * pixels
// |snapped coordinate| <= RASTER_COORD_LIMIT subpixels ((G + 1) * size / 2 * 256 <= 2^28 + 2^20): coordinate
// differences fit in 31 bits, edge-function products and constants in 61 bits, so 64-bit edge functions are exact.
#define RASTER_COORD_LIMIT (1 << 29)  // subpixels

// ---- Screen hierarchy ----------------------------------------------------------------------------------------
#define RASTER_MAX_VIEWPORT 8192                                     // pixels per axis (1 .. 8192 supported)
#define RASTER_TILE_LOG2 3                                           // tile = 8x8 pixels
#define RASTER_TILE_SIZE (1 << RASTER_TILE_LOG2)                     // pixels per tile side
#define RASTER_TILE_PIXELS (RASTER_TILE_SIZE * RASTER_TILE_SIZE)     // pixels per tile (64)
#define RASTER_BIN_LOG2 4                                            // bin = 16x16 tiles (BinSize / TileSize)
#define RASTER_BIN_TILES (1 << RASTER_BIN_LOG2)                      // tiles per bin side
#define RASTER_BIN_PIXEL_LOG2 (RASTER_BIN_LOG2 + RASTER_TILE_LOG2)   // bin = 128x128 pixels
#define RASTER_BIN_TILE_COUNT (RASTER_BIN_TILES * RASTER_BIN_TILES)  // tiles per bin (256)
#define RASTER_MAX_BINS_PER_AXIS (RASTER_MAX_VIEWPORT >> RASTER_BIN_PIXEL_LOG2)  // 64
#define RASTER_MAX_BINS (RASTER_MAX_BINS_PER_AXIS * RASTER_MAX_BINS_PER_AXIS)    // 4096 = what one scan covers

// ---- Clipping ------------------------------------------------------------------------------------------------
// Near plane + 4 guard-band planes: a triangle becomes a convex polygon of at most 3 + 5 vertices, fanned into at
// most 6 triangles (a near-plane crossing alone gives at most 2).
#define RASTER_CLIP_PLANES 5
#define RASTER_MAX_CLIP_VERTICES (3 + RASTER_CLIP_PLANES)         // polygon vertices after clipping
#define RASTER_MAX_CLIP_TRIANGLES (RASTER_MAX_CLIP_VERTICES - 2)  // fan triangles per input triangle

// ---- Work-group sizes ----------------------------------------------------------------------------------------
// Structural (fixed by the layout above, not tunable):
#define RASTER_COARSE_WG RASTER_BIN_TILE_COUNT                // coarse: one work-group per bin, one item per tile
#define RASTER_FINE_WG RASTER_TILE_PIXELS                     // fine: one work-group per tile, one item per pixel
#define RASTER_SCAN_WG 256                                    // scan: one work-group over every bin
#define RASTER_SCAN_ITEMS (RASTER_MAX_BINS / RASTER_SCAN_WG)  // bins per scan work-item (16)
// Tunable (work-items per group), one row per device class; the host picks a row (raster::workGroupsFor(),
// raster/plan.cpp) and passes it as -DRASTER_WG_SETUP=... -DRASTER_WG_BIN=... -DRASTER_WG_GBUFFER=...
// -DRASTER_WG_FINE=... -DRASTER_WG_COARSE=... -DRASTER_BIN_RUN=...; a row counts only after the Raster* tests pass
// with it (PoCL: checked with 64/64/64/64/1/32, 64/64/64/0/0/1 and 128/256/32/1/4/7; NVIDIA: not yet run on the
// device). fine selects the fine stage's layout (raster/fine.cl): 0 = one work-group of RASTER_FINE_WG items per tile
// (an item per pixel), N > 0 = N tiles per work-group, an item per tile (CPUs; it also selects setup's CPU path,
// RASTER_SETUP_VECTOR in setup.cl). coarse selects the coarse stage's layout (raster/coarse.cl): 0 = a work-group of
// RASTER_COARSE_WG items per bin (an item per tile), N > 0 = N bins per work-group, an item per bin (CPUs). bin run is
// the records each bin_count / bin_fill work-item walks (raster/bin.cl): 1 on GPUs, a run on CPUs, where an item
// merges consecutive entries into one bin into one atomic.
// clang-format off
//                               setup  bin  gbuffer  fine  coarse  bin run
#define RASTER_WG_ROW_DEFAULT      64,   64,   64,      0,     0,     1  // any device
#define RASTER_WG_ROW_NVIDIA      128,  128,  128,      0,     0,     1  // NVIDIA H100 (OpenCL 3.0 driver)
#define RASTER_WG_ROW_POCL         64,   64,   64,     64,     1,    32  // PoCL 3.1 CPU (loops: small groups suffice)
// clang-format on

// ---- Record values -------------------------------------------------------------------------------------------
#define RASTER_NO_TRIANGLE 0xffffffffu  // triangle id of background pixels
#define RASTER_SATURATED 0xffffffffu    // a queue offset past every capacity: write nothing
#define RASTER_FLAG_VALID 1u            // RasterTriangle.flags: the record is drawn
#define RASTER_FLAG_OWNS_EDGE0 2u       // edge k owns its samples (top-left): bit 1 << (k+1)
#define RASTER_FLAG_ALPHA 16u           // alpha-tested: the fine stage samples its material's alpha before the depth test
#define RASTER_FLAG_NONCASTER 32u       // casts nothing (RasterView::casterLight), drawn for recordCasterTiles
#define RASTER_FLAG_ALPHA_SHIFT 6       // flags >> 6: its AlphaTriangle (so at most 2^26 alpha-tested triangles)
// Per-triangle material bits (SceneBuffers::triangleBits, read by setup when RasterViewParams::triangleBits is set).
#define RASTER_TRI_SINGLE_SIDED 1u  // culled when back-facing in views that cull single-sided triangles
#define RASTER_TRI_ALPHA 2u         // alpha-tested; bits >> RASTER_TRI_ALPHA_SHIFT: its AlphaTriangle
#define RASTER_TRI_ALPHA_SHIFT 2

// Which side setup drops (RasterViewParams::solidSides: a code per triangle; the view's own culling: RASTER_CULL_CW):
// the triangles of a solid facing away from the view's centre, clockwise in window space where the solid's outside is
// counter-clockwise, and the other way round for solids wound inside out.
#define RASTER_CULL_NONE 0u
#define RASTER_CULL_CW 1u   // drop triangles clockwise in window space
#define RASTER_CULL_CCW 2u  // drop triangles counter-clockwise in window space
// Which light a view leaves out non-casters for (RasterViewParams::casterSource; RasterView::casterLight): none, a
// ball (a spot or point light's centre and radius) or a cone of directions (a sun's direction and angular radius).
#define RASTER_CASTERS_ALL 0u
#define RASTER_CASTERS_BALL 1u
#define RASTER_CASTERS_CONE 2u
#define RASTER_MAX_ALPHA_TRIANGLES (1u << (32 - RASTER_FLAG_ALPHA_SHIFT))  // alpha-tested triangles per scene

// DepthMode (raster/rasterizer.h) as the kernels see it.
#define RASTER_DEPTH_NDC 0       // window depth in [0, 1]
#define RASTER_DEPTH_VIEW_Z 1    // -z_eye, eye-space units
#define RASTER_DEPTH_DISTANCE 2  // |p_eye|, eye-space units

#endif
