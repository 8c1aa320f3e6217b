// lighting.tiled (frame.md section 5): direct light from the sun, directional lights and each
// pixel's froxel list of lights.cluster, per 16×16-pixel tile, split into diffuse and specular
// (RGBA16F). Tiles are classified (passes/lighting/tiled_layout.h) and each class shaded by one
// indirect dispatch whose arguments the pass computes itself; tiled.comp states the phases and
// the lighting model. Outputs also lighting.tile_classes (the dispatches) and lighting.tile_lists
// (each tile's class and the lists), the same on every run. The sun's shadow is shadow.sun's red
// channel (shadow.sun_resolve; 1 where it was skipped), times its contact shadow, a short
// screen-space march (contact_*). A spot light with a map this frame (shadow.local_slots) is
// shadowed by it (shadow.local_moments, local_*): with 4 moments (shadow.local_data's counts.y)
// the Hamburger 4MSM lower bound on the fraction of the filter in front of the receiver, with 2
// Chebyshev's upper bound on the fraction lit; either with light-bleeding reduction. Other local
// lights have no shadow.
#include <array>

#include "passes/core/context.h"
#include "passes/lighting/stage.h"
#include "passes/lighting/tiled_layout.h"
#include "passes/shadow/local_layout.h"

namespace nightcap {

namespace {

ComparisonContract lighting_contract() {
  return ComparisonContract::floats(0x1p-23, 0x1p-9,
                                    "each device within 2^-10 relative (2^-24 absolute) of the double-precision "
                                    "BRDF for sun, point and spot lights where its float inputs allow "
                                    "(tests/unit/lighting_tiled_test.cpp): two within twice that");
}

}  // namespace

BufferSchema tile_classes_schema() { return NC_SCHEMA_OF(GpuTileClasses, NC_TILE_CLASSES_FIELDS); }

BufferSchema tile_entry_schema() { return NC_SCHEMA_OF(GpuTileEntry, NC_TILE_ENTRY_FIELDS); }

PassDecl lighting_tiled_pass() {
  ImageDecl hdr{VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour};
  return PassDecl("lighting.tiled", PassType::compute)
      .read("frame.constants", Use::uniform_buffer)
      .read("frame.views", Use::uniform_buffer)
      .read("frame.lights", Use::storage_read)
      .read("gbuffer.albedo", Use::sampled)
      .read("gbuffer.normal", Use::sampled)
      .read("gbuffer.material", Use::sampled)
      .read("scene.depth", Use::sampled)
      .read("depth.linear", Use::sampled)
      .read("lights.clusters", Use::sampled)
      .read("lights.cluster_indices", Use::storage_read)
      .read("lights.cluster_stats", Use::storage_read)
      .read("lighting.ltc_inverse", Use::sampled)
      .read("lighting.ltc_magnitude", Use::sampled)
      .read("shadow.sun", Use::sampled)
      .read("shadow.local_data", Use::uniform_buffer)
      .read("shadow.local_slots", Use::storage_read)
      .read("shadow.local_moments", Use::sampled)
      // Bilinear over the moments: the filter moment maps are made for, and no stair steps at a
      // shadow's edge.
      .sampler("shadow.local_moments", bilinear_clamp_sampler())
      .write("lighting.diffuse", Use::storage_write, hdr)
      .write("lighting.specular", Use::storage_write, hdr)
      .write("lighting.tile_classes", Use::storage_write, BufferDecl{kinds::buffer, sizeof(GpuTileClasses)})
      .write("lighting.tile_lists", Use::storage_write,
             BufferDecl{kinds::buffer, uint64_t(kLightingTileCapacity) * sizeof(GpuTileEntry)})
      .layout("lighting.tile_classes", tile_classes_schema())
      .layout("lighting.tile_lists", tile_entry_schema())
      .param_float("intensity_scale", 1.0, 0.0, 1e6, "multiplies every light's intensity")
      .param_float("min_roughness", 0.03, 0.0, 1.0, "roughness floor: keeps point highlights finite in half floats")
      .choice("tube_nodes", 8, numbered_choices(std::array<uint32_t, 4>{2, 4, 8, 16}),
              "Gauss-Legendre nodes along each tube line for its specular and ranged diffuse: 2, 4, 8 or 16")
      .param_float("contact_length", 0.5, 0.0, 10.0, "metres the sun's contact shadow marches toward the sun")
      .param_int("contact_steps", 8, 0, 64, "steps of the contact shadow's march (0: no contact shadow)")
      .param_float("contact_thickness", 0.5, 0.001, 100.0,
                   "metres in front of the march beyond which a surface does not occlude it")
      .param_float("local_bias", 0.002, 0.0, 0.1,
                   "linear depth (a fraction of the light's range) a receiver may lie behind its map and stay lit")
      .param_float("local_min_variance", 2e-5, 0.0, 0.01,
                   "2 moments: floor of the moments' variance, which keeps a flat receiver lit through 16-bit rounding")
      .param_float("local_bleeding", 0.2, 0.0, 0.99,
                   "light-bleeding reduction: visibilities below this read as shadow, the rest rescaled")
      .param_float("local_moment_bias", 3e-5, 0.0, 0.1,
                   "4 moments: weight of (0.5, 0.5, 0.5, 0.5) mixed into them (Peters and Klein's α for 16 bits), "
                   "which keeps their Hankel matrix invertible through rounding")
      .compare("lighting.diffuse", lighting_contract())
      .compare("lighting.specular", lighting_contract())
      .skip_when([](const SkipContext& frame) {
        const bool lit = frame.features.count("sun") || frame.features.count("local_lights");
        return lit ? std::string() : std::string("scene has no lights");
      })
      .skip_when_cleared({"scene.depth"})
      .push_constants<TiledConstants>()
      .shader("lighting/tiled.comp")
      .run([](PassContext& ctx) {
        const ImageExtent size = ctx.desc("lighting.diffuse").extent;
        const TiledConstants constants{
            group_count(size.width, kLightingTile),       group_count(size.height, kLightingTile),
            float(ctx.param_float("intensity_scale")),    float(ctx.param_float("min_roughness")),
            float(ctx.param_float("contact_length")),     float(ctx.param_float("contact_thickness")),
            uint32_t(ctx.param_int("contact_steps")),     float(ctx.param_float("local_bias")),
            float(ctx.param_float("local_min_variance")), float(ctx.param_float("local_bleeding")),
            float(ctx.param_float("local_moment_bias"))};
        // Each phase is its own pipeline (tiled.comp's constant `phase`): lavapipe runs every
        // side of a branch, so one pipeline switching on a push constant paid for every phase
        // in each dispatch (phase 1's loops in every workgroup of the shading).
        const int32_t tube_nodes = int32_t(ctx.param_int("tube_nodes"));
        // The moments' reconstruction too: shadow.local_plan's record says which were written.
        const int32_t moments = local_shadow_moments(ctx.host("shadow.local_data"), "lighting.tiled");
        auto begin_phase = [&](int32_t phase) {
          ctx.bind_pipeline({phase, tube_nodes, moments});
          ctx.push_declared();
          ctx.push_constants(constants);
        };
        begin_phase(0);
        vkCmdDispatch(ctx.cmd(), constants.tiles_x, constants.tiles_y, 1);
        ctx.storage_barrier();
        begin_phase(1);
        vkCmdDispatch(ctx.cmd(), 1, 1, 1);
        ctx.storage_barrier();
        // The classes write disjoint tiles and read only what phases 0 and 1 wrote; the
        // barriers between them are for the synchronization validation, which counts the
        // arguments' binding (written in phase 1) as written by every dispatch.
        for (uint32_t tile_class = 1; tile_class <= kLightingTileClasses; ++tile_class) {
          if (tile_class > 1) ctx.storage_barrier();
          begin_phase(int32_t(tile_class + 1));
          ctx.dispatch_indirect("lighting.tile_classes", (tile_class - 1) * sizeof(glm::uvec4));
        }
      });
}

}  // namespace nightcap
