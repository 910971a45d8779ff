#include "ground_pass.h"

#include <cstring>
#include <limits>

namespace conde_physics {
namespace render_detail {
namespace {

constexpr float kNoHit = std::numeric_limits<float>::infinity();

// Four lanes of floats / ints (GCC and Clang vector extensions: one SSE2 register on plain
// x86-64, NEON on ARM; wider vectors get split badly without AVX). Comparisons give Ints masks,
// -1 for true. Where the CPU has AVX2 (checked at run time), the ground pass runs on eight
// lanes instead; its helpers are always inlined, so no 32-byte vector crosses a call without
// AVX (which is what -Wpsabi warns about).
#pragma GCC diagnostic ignored "-Wpsabi"
typedef float Floats __attribute__((vector_size(16)));
typedef std::int32_t Ints __attribute__((vector_size(16)));
typedef float Floats8 __attribute__((vector_size(32)));
typedef std::int32_t Ints8 __attribute__((vector_size(32)));
template <typename V, typename T>
__attribute__((always_inline)) inline V loadLanes(const T* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <typename V, typename T>
__attribute__((always_inline)) inline void storeLanes(T* p, const V& v) {
  std::memcpy(p, &v, sizeof v);
}

// Ground hit of `count` rays (a multiple of the lane count) and their texel addresses, one
// vector of lanes at a time.
template <typename F, typename I>
__attribute__((always_inline)) inline void groundPass(const GroundFrame& g, const float* __restrict rx,
                                                      const float* __restrict ry, const float* __restrict rz, int count,
                                                      const GroundTile& out) {
  constexpr int kWidth = sizeof(F) / sizeof(float);
  for (int i = 0; i < count; i += kWidth) {
    const F x = loadLanes<F>(rx + i), y = loadLanes<F>(ry + i), z = loadLanes<F>(rz + i);
    const F dx = g.rot[0][0] * x + g.rot[0][1] * y + g.rot[0][2] * z;
    const F dy = g.rot[1][0] * x + g.rot[1][1] * y + g.rot[1][2] * z;
    const F dz = g.rot[2][0] * x + g.rot[2][1] * y + g.rot[2][2] * z;
    const F down = -1.0f / dz;  // > 0 for rays that go down
    const F t = g.camera_height * down;
    const I hit = (dz < 0.0f) & (t >= g.near) & (t <= g.far);
    const F u = g.u_at_camera + t * dx * g.tex_u_per_m;
    const F v = g.v_at_camera - t * dy * g.tex_v_per_m;
    const I on_texture = (u >= -0.5f) & (u <= g.u_limit) & (v >= -0.5f) & (v <= g.v_limit);
    // Mipmap level from the exponent bits of 2 rho^2, and 2^-level the same way. (Lanes
    // without a ground hit may hold inf or NaN here; their kind is kSky.)
    const F area2 = g.footprint_area_scale * (down * down * down);
    I l = ((reinterpret_cast<const I&>(area2) >> 23) - 127) >> 1;
    l = l < 0 ? 0 : l;
    l = l > g.max_level ? g.max_level : l;
    const I scale_bits = (127 - l) << 23;
    const F scale = reinterpret_cast<const F&>(scale_bits);
    const F uc = u > g.u_limit ? g.u_limit : (u < -0.5f ? -0.5f : u);
    const F vc = v > g.v_limit ? g.v_limit : (v < -0.5f ? -0.5f : v);
    F ul = (uc + 0.5f) * scale - 0.5f;
    F vl = (vc + 0.5f) * scale - 0.5f;
    ul = ul < 0.0f ? 0.0f : ul;
    vl = vl < 0.0f ? 0.0f : vl;
    const I iu = __builtin_convertvector(ul, I), iv = __builtin_convertvector(vl, I);
    storeLanes(out.depth + i, F(hit ? t : kNoHit));
    storeLanes(out.kind + i, I(hit & (on_texture ? kTexture : kPlainGround)));
    storeLanes(out.level + i, l);
    storeLanes(out.texel_u + i, iu);
    storeLanes(out.texel_v + i, iv);
    storeLanes(out.weight_u + i, __builtin_convertvector((ul - __builtin_convertvector(iu, F)) * 256.0f, I));
    storeLanes(out.weight_v + i, __builtin_convertvector((vl - __builtin_convertvector(iv, F)) * 256.0f, I));
  }
}

void groundPass4(const GroundFrame& g, const float* rx, const float* ry, const float* rz, int count,
                 const GroundTile& out) {
  groundPass<Floats, Ints>(g, rx, ry, rz, count, out);
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same on eight lanes. (The bilinear read stays scalar, in render(): AVX2 gathers made it
// slower on this machine.)
__attribute__((target("avx2"))) void groundPass8(const GroundFrame& g, const float* rx, const float* ry,
                                                 const float* rz, int count, const GroundTile& out) {
  groundPass<Floats8, Ints8>(g, rx, ry, rz, count, out);
}
#endif

}  // namespace

bool haveAvx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool have = __builtin_cpu_supports("avx2");
  return have;
#else
  return false;
#endif
}

GroundPassFunction groundPassFunction(bool allow_wide) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (haveAvx2() && allow_wide) return groundPass8;
#endif
  return groundPass4;
}

}  // namespace render_detail
}  // namespace conde_physics
