// A per-pixel rotation for tap patterns: interleaved gradient noise of the pixel coordinates (Jimenez, "Next
// Generation Post Processing in Call of Duty: Advanced Warfare", SIGGRAPH 2014 course), so that the banding of one
// fixed pattern becomes fine, high-frequency noise. Shared by pcf.cl and pcss.cl; and a hash for jittered taps.
#ifndef PENUMBRA_KERNELS_SHARED_ROTATION_H
#define PENUMBRA_KERNELS_SHARED_ROTATION_H

inline float rot_frac(float v) { return v - floor(v); }  // OpenCL C's fract() needs an out-pointer

// Angle in [0, 2 pi) for pixel (x, y).
inline float rot_angle(uint x, uint y) {
  return 6.2831853f * rot_frac(52.9829189f * rot_frac(0.06711056f * (float)x + 0.00583715f * (float)y));
}

// Low-bias 32-bit integer hash (Wellons' "lowbias32" constants) to a uniform float in [0, 1): per-tap jitter.
inline float rot_hash01(uint x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return (float)(x >> 8) * (1.0f / 16777216.0f);
}

// d rotated by the angle whose cosine and sine are cs.
inline float2 rot_apply(float2 cs, float2 d) { return (float2)(cs.x * d.x - cs.y * d.y, cs.y * d.x + cs.x * d.y); }

#endif
