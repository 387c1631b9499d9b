// Double-precision reference of VSSM's per-pixel algorithm (Yang et al. 2010, Algorithms 1 and 2), written from
// the paper independently of kernels/vssm.cl: box moments from a double SAT (of block means where satReduce > 1), the
// HSM from ref::minMaxPyramid, eq. 4/5 blocker depths, uniform subdivision and adaptive subdivision as a recursive
// quad-tree walk (the kernel walks the same tree by Child/Next links), PCF leaves and the 3x3 jittered contact PCF.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace penumbra::ref {

// What the algorithm needs of the light's view (kernels/shared/light_view.h's meaning).
struct VssmLight {
  bool spot = true;
  double lightSize = 0.0;   // spot: disk radius; directional: tan(angular radius)
  double texelScale = 1.0;  // spot: texel width per unit depth; directional: texel width
  double zNear = 0.0, zFar = 1.0;
};

struct VssmSettings {
  int searchScheme = 1, shadeScheme = 2;  // 0 none, 1 uniform, 2 adaptive (VSSM_SCHEME_*)
  int m = 5, n = 8, levels = 3, leafTaps = 2;
  double litVariance = 0.0;   // normalised depth^2
  double contactDepth = 0.0;  // world
  double maxRadius = 128.0;   // texels
  double minVariance = 1e-6;  // normalised depth^2
  double planarMaxLit = 1.0;  // eq. 4 on the whole search kernel only while P <= this
  int diskStrips = 0;         // beyond the paper: 0 square kernels, else disks of at most this many strips
  double stackedSpread = 0;   // beyond the paper: the stacked-blocker PCF fallback's threshold (0: never)
  int stackedTaps = 8;        // its jittered taps per side
  int searchNarrowings = 0;   // beyond the paper: narrowings of the search kernel by its nearest texel
  int satReduce = 1;          // beyond the paper: the moments' table over blocks of satReduce^2 texels
  bool firstMoment = false;   // beyond the paper: the shading's Chebyshev bound capped by the first moment's share
  double tiltShare = 0;       // beyond the paper: a tilted receiver's penumbra kernel filtered by the taps (0: never)
};

struct VssmReceiverIn {
  double u = 0, v = 0;         // texel coordinates
  double depth = 0, bias = 0;  // world light depth, constant bias
  double biasSlope = 0;        // bias per texel of offset
  uint32_t seed = 0;           // pixel index (contact PCF jitter)
};

struct VssmResult {
  double visibility = 1, blocker = 0, penumbra = 0;
  int visited = 0, path = 0;  // path: VSSM_PATH_* values
};

class VssmReference {
 public:
  VssmReference(const std::vector<float>& depth, uint32_t width, uint32_t height, const VssmLight& light,
                const VssmSettings& settings);
  VssmResult pixel(const VssmReceiverIn& receiver) const;
  // Searches the no-blocker test ended only by descending below its first level (vssm.cl vssm_no_blocker), over
  // every pixel() so far.
  size_t descents() const { return descents_; }

 private:
  struct Rx;
  struct Sums;
  double corner(double u, double v, int channel) const;
  std::pair<double, double> boxMoments(double lx, double ly, double hx, double hy) const;
  std::pair<double, double> hsmRange(double lx, double ly, double hx, double hy) const;
  bool nodeMayBlock(const Rx& r, double w, size_t l, int x, int y) const;
  bool noBlocker(const Rx& r, double w) const;
  size_t coverLevel(double ax, double bx, double ay, double by, int most, std::pair<int, int>& sx,
                    std::pair<int, int>& sy) const;
  double fetch(int x, int y) const;
  double bilinearLit(double u, double v, double depth) const;
  double tapDepth(const Rx& r, double u, double v) const;
  double penumbraTexels(double receiver, double occluder) const;
  bool visit(const Rx& r, double lx, double ly, double hx, double hy, bool leaf, bool search, Sums& s) const;
  void adaptive(const Rx& r, double lx, double ly, double sx, double sy, int level, int maxLevel, bool search,
                Sums& s) const;
  // The kernel of half-width w around the receiver: the square, or the disk's strips (lo, hi per strip).
  std::vector<std::pair<std::array<double, 2>, std::array<double, 2>>> kernelBoxes(const Rx& r, double w) const;
  std::pair<double, double> kernelMoments(const Rx& r, double w) const;
  void subdivide(const Rx& r, double w, bool search, Sums& s) const;
  double blocker(const Rx& r, double w, double zmin, bool& subdivided, int& visited) const;
  // path: 0 (lit) or 1 (umbra) where the min-max range over the kernel's square decided, 7 for a tilted receiver's
  // taps, 6 for the stacked-blocker fallback, else unchanged.
  double shade(const Rx& r, double w, double zocc, bool& subdivided, int& visited, int& path) const;
  double litShare(const Rx& r, double mean, double variance, double zocc) const;
  double contact(const Rx& r, double lo[2], double hi[2]) const;
  bool stacked(double zocc, double zmin, double t) const;
  // search: the mean normalised depth of the taps that block (-1: none); else the lit share (vssm.cl).
  double stackedTaps(const Rx& r, double w, bool search) const;

  std::vector<float> depth_;
  uint32_t width_, height_;
  VssmLight light_;
  VssmSettings settings_;
  // (satWidth + 1) x (satHeight + 1) prefix sums of the blocks' mean z and z^2 (texels beyond the map: z = 1)
  std::vector<double> sat_[2];
  uint32_t satWidth_, satHeight_;
  std::vector<std::vector<std::pair<float, float>>> hsm_;
  std::vector<std::pair<uint32_t, uint32_t>> hsmSizes_;
  mutable size_t descents_ = 0;  // statistics for the kernel suite (descents())
};

}  // namespace penumbra::ref
