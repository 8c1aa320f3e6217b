// Fixed-function state a pass declares with itself (PassDecl::raster, depth_stencil, blend):
// the pipeline cache builds it and the capture records it, so no pass sets it by hand.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>

namespace nightcap {

struct DepthBias {
  // depth += constant·r + slope·max|∂z/∂x|,|∂z/∂y|, limited to ±clamp (0: unlimited), where r is
  // the smallest resolvable step of the depth format at the primitive's depth.
  float constant = 0.0f, slope = 0.0f, clamp = 0.0f;
  bool enabled() const { return constant != 0.0f || slope != 0.0f; }
};

struct RasterState {
  VkCullModeFlags cull_mode = VK_CULL_MODE_NONE;
  VkFrontFace front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  // Scene draws change both per draw (double-sided materials are not culled, mirrored
  // transforms flip the winding): they become dynamic state, set from the declared ones.
  bool per_draw_faces = false;
  DepthBias depth_bias;

  static RasterState per_draw(VkCullModeFlags cull_mode, VkFrontFace front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE) {
    return {cull_mode, front_face, true, {}};
  }
};

struct DepthStencilState {
  bool test = false, write = false;
  VkCompareOp compare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reversed-Z
  // Stencil: passes where `stencil_compare` against the dynamic reference holds, and writes the
  // reference (masked) where depth passes too when `stencil_write`.
  VkCompareOp stencil_compare = VK_COMPARE_OP_ALWAYS;
  bool stencil_write = false;
  uint32_t stencil_read_mask = 0xff, stencil_write_mask = 0xff;
  bool stencil_test() const { return stencil_write || stencil_compare != VK_COMPARE_OP_ALWAYS; }

  static DepthStencilState depth(VkCompareOp compare, bool write) {
    DepthStencilState s;
    s.test = true;
    s.write = write;
    s.compare = compare;
    return s;
  }
  DepthStencilState writing_stencil() const {
    DepthStencilState s = *this;
    s.stencil_write = true;
    return s;
  }
};

// One colour attachment's blending: result = src·src_factor (op) dst·dst_factor.
struct BlendState {
  bool enabled = false;
  VkBlendFactor src_color = VK_BLEND_FACTOR_ONE, dst_color = VK_BLEND_FACTOR_ZERO;
  VkBlendOp color_op = VK_BLEND_OP_ADD;
  VkBlendFactor src_alpha = VK_BLEND_FACTOR_ONE, dst_alpha = VK_BLEND_FACTOR_ZERO;
  VkBlendOp alpha_op = VK_BLEND_OP_ADD;
  VkColorComponentFlags write_mask = 0xf;

  static BlendState additive() {
    BlendState b;
    b.enabled = true;
    b.dst_color = b.dst_alpha = VK_BLEND_FACTOR_ONE;
    return b;
  }
  // a·src + (1 − a)·dst on rgb, a the source's alpha; the target's alpha is not written (a
  // G-buffer keeps its flags there).
  static BlendState over_rgb() {
    BlendState b;
    b.enabled = true;
    b.src_color = VK_BLEND_FACTOR_SRC_ALPHA;
    b.dst_color = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    b.write_mask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT;
    return b;
  }
};

}  // namespace nightcap
