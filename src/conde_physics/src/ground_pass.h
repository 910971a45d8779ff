// The ground pass of CameraRenderer (private to conde_physics): for a tile of pixel rays, where
// each ray meets the ground plane z = 0, what it sees there (sky, plain ground, texture), and the
// texels and weights of the bilinear read from the mipmap level that matches its footprint.
// Vectorised with GCC/Clang vector extensions: four lanes everywhere, eight where the CPU has AVX2.
#pragma once

#include <cstddef>
#include <cstdint>

#include "conde_physics/render_scene.h"

namespace conde_physics {
namespace render_detail {

// What a ray sees of the ground: nothing (sky), the plain ground, or the texture.
constexpr std::int32_t kSky = 0, kPlainGround = 1, kTexture = 2;

// The per-frame numbers of the ground pass (see render()).
struct GroundFrame {
  float rot[3][3];  // world_R_optical
  float camera_height = 0.0f, near = 0.0f, far = 0.0f;
  float u_at_camera = 0.0f, v_at_camera = 0.0f, tex_u_per_m = 0.0f, tex_v_per_m = 0.0f;
  float u_limit = 0.0f, v_limit = 0.0f, footprint_area_scale = 0.0f;
  std::int32_t max_level = 0;
  // The texture: packed texels (R in the low byte, then G, B), its mipmap levels,
  // and the packed colours of the plain ground and the sky.
  const std::uint32_t* texels = nullptr;
  const RenderScene::TextureLevel* levels = nullptr;
  std::uint32_t ground_packed = 0, sky_packed = 0;
};

// Per pixel of a tile: depth of the ground hit, kind, mipmap level, top-left texel and 8-bit
// bilinear weights.
struct GroundTile {
  float* depth;
  std::int32_t *kind, *level, *texel_u, *texel_v, *weight_u, *weight_v;
};

// Bilinear read of one pixel's texels: red and blue, then green, in 16-bit lanes of one word.
inline std::uint32_t bilinearTexel(const GroundFrame& g, const GroundTile& t, int k) {
  const RenderScene::TextureLevel& level = g.levels[t.level[k]];
  const int stride = level.width_px + 1;
  const std::uint32_t* p = g.texels + level.first_texel + static_cast<size_t>(t.texel_v[k]) * stride + t.texel_u[k];
  const std::uint32_t wu = static_cast<std::uint32_t>(t.weight_u[k]), wv = static_cast<std::uint32_t>(t.weight_v[k]);
  const std::uint32_t p00 = p[0], p01 = p[1], p10 = p[stride], p11 = p[stride + 1];
  constexpr std::uint32_t kPair = 0x00FF00FFu;
  const std::uint32_t rb_top = (((p00 & kPair) * (256 - wu) + (p01 & kPair) * wu) >> 8) & kPair;
  const std::uint32_t rb_bottom = (((p10 & kPair) * (256 - wu) + (p11 & kPair) * wu) >> 8) & kPair;
  const std::uint32_t g_top = ((((p00 >> 8) & kPair) * (256 - wu) + ((p01 >> 8) & kPair) * wu) >> 8) & kPair;
  const std::uint32_t g_bottom = ((((p10 >> 8) & kPair) * (256 - wu) + ((p11 >> 8) & kPair) * wu) >> 8) & kPair;
  const std::uint32_t rb = ((rb_top * (256 - wv) + rb_bottom * wv) >> 8) & kPair;
  const std::uint32_t gg = ((g_top * (256 - wv) + g_bottom * wv) >> 8) & kPair;
  return rb | (gg << 8);
}

using GroundPassFunction = void (*)(const GroundFrame&, const float*, const float*, const float*, int,
                                    const GroundTile&);

// The pass for this CPU: eight lanes where it has AVX2 and `allow_wide`, else four lanes.
GroundPassFunction groundPassFunction(bool allow_wide);
bool haveAvx2();  // this CPU has AVX2 (and the build targets x86-64)

}  // namespace render_detail
}  // namespace conde_physics
