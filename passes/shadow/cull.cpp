// shadow.cull (CPU): the sun's cascades for this frame and what each draws. frame.md's
// shadow.cascades culls "per cascade against an up-to-8-plane convex volume"; culling is CPU
// work, and a CPU pass is how the graph records it, so it is its own pass ahead of the GPU one.
//
// Cascades: the view from znear to `max_distance` split by the practical scheme (Zhang et al.
// 2006: `lambda` between the logarithmic and the uniform split). Each cascade is an orthographic
// projection along the sun around its slice's bounding sphere, whose radius depends on the
// camera's lens alone, so the map's footprint does not change as the camera turns; its centre is
// snapped to whole texels in world (not camera-relative) light space, so a moving camera does
// not make the shadow's edges crawl. Light depth spans the whole scene's along the sun (its
// static box and the moving instances), the same for every cascade, whatever is culled, so
// culling changes no depth the map stores.
//
// Casters are the opaque instances, static and moving, at the level of detail the main view
// draws. A caster is kept for a cascade when its box meets the slice extruded toward the sun
// (the slice's faces that face away from the sun, and planes through its silhouette edges along
// the sun's direction), every plane pushed out by `margin_texels`: a box outside that shadows
// no receiver of the slice, nor any texel the resolve's filter reads around one, as long as the
// margin covers the filter ((filter_radius + 1)·√2 texels; and, along the sun, receiver_slope
// times that for the resolve's receiver-plane bias). A caster inside it is still dropped
// when its box swept along the sun to the cascade's far light depth or the scene's lowest point
// (where its shadow can fall), grown by the margins, is hidden behind cull.main's occluders (cull.occlusion): whatever
// it shadows is then no visible pixel. So culling on and off give the same shadow.sun (tested).
// A caster that passes both is still dropped when, seen from the sun, it lies wholly behind
// shadow.distant_occluders (level 0 of the distant shadow, with only the occluders every cascade
// draws too: LightOccluders says how) [004 §2.2.3]. Last, with a time-of-day table (scene.tod,
// `render --tod`), a caster hidden from the light at
// the baked hours around this one is dropped (passes/scene/time_of_day.cpp says why that changes
// no texel of the map at a baked hour).
//
// Caching across frames (`cache`, [004 §2]): each cascade's draws list the static casters of
// its redrawn tiles, then its moving casters. shadow.cascades_static keeps the static casters'
// depth as history and shadow.cascades draws the moving ones over it each frame. For a layer to
// carry over as the camera moves, it must depend on nothing but where it lies: every cascade
// spans the same light depth (the scene's, LightRange), its side depends on the lens alone and
// its centre moves by whole texels, so the previous frame's texels are this frame's, shifted
// (shadow.cascades_static copies them). The static layer is cut into `tiles`² tiles, and a tile
// holds the depth of every static caster across the sun from it, at the level the view draws
// (not only those in the slice's volume, which moves with the view; a caster outside it changes
// no visibility in the slice: it shadows no receiver there, or lies beyond them from the sun).
// This pass reads its own previous record (history: empty on frame 0 and after a cut). The
// texels a move uncovers (a strip of columns and one of rows, a few texels wide) are drawn each
// frame under their own scissors: a tile that missed nothing else is then complete. A tile is
// stale when some texel of it came from a tile that was not complete, or when a static caster
// over it changed its level of detail, or its drawn-or-not, since a frame earlier; it is drawn
// again whole. Units (a cascade's strips, a tile) are redrawn as many as fit in
// `budget_triangles`, those the view needs first (the tiles the slice covers, grown by the
// resolve's margin; strips before tiles), tiles that waited longest first, else finest cascade
// first; the rest wait (`pending`, `unit_waiting`), and shadow.sun_resolve
// reads no texel of a tile that is not complete: a pixel there falls back to the next cascade
// that holds its filter, or the distant levels. A reset (no history, the layers' frame changed:
// the sun, the light depth's range, the lens, a parameter, the hour) draws every static layer
// whole, whatever the budget. A still camera draws no static caster after frame 0. With `cache`
// 0 every static layer is drawn whole each frame, culled by the volume and the view's occluders
// as the moving casters are. Why a frame reset is ShadowCullStats::reset.
//
// The pass runs a ShadowCuller (shadow_culler.h); the volumes it culls by are cull_volume.h's and
// its test against the sun's occluders is light_occluders.h's.
#include "passes/core/context.h"
#include "passes/frame/gpu_types.h"
#include "passes/shadow/shadow_culler.h"
#include "passes/shadow/shadow_layout.h"
#include "passes/shadow/shadow_params.h"
#include "passes/shadow/stage.h"

namespace nightcap {

PassDecl shadow_cull_pass() {
  return PassDecl("shadow.cull", PassType::cpu)
      .read("frame.camera", Use::host)
      .read("frame.constants", Use::host)
      .read("scene.instances", Use::host)
      .read("scene.meshes", Use::host)
      .read("scene.hierarchy", Use::host)
      .read("scene.materials", Use::host)
      .read("cull.occlusion", Use::host)
      .read("scene.tod", Use::host)
      .read("shadow.distant_data", Use::host)
      .read("shadow.distant_occluders", Use::host)
      .read_previous("shadow.cull_stats", Use::host)
      .write("shadow.cascade_data", Use::host, BufferDecl{kinds::buffer})
      .write("draws.shadow.cascades", Use::host, BufferDecl{kinds::draw_list})
      .write("shadow.cull_stats", Use::host, BufferDecl{kinds::buffer})
      .layout("shadow.cascade_data", shadow_cascades_schema())
      .layout("draws.shadow.cascades", draw_schema())
      .layout("shadow.cull_stats", shadow_cull_stats_schema())
      .param(sun_shadow_resolution())
      .param_float("max_distance", 120, 1, 20000,
                   "metres along the view where the last cascade ends (no sun shadow beyond)")
      .param_float("lambda", 0.75, 0, 1, "practical split: 1 logarithmic, 0 uniform")
      .param_float("margin_texels", 6, 0, 64,
                   "texels each culling plane is pushed out: at least (shadow.sun_resolve.filter_radius + 1)·√2")
      .param_float("receiver_slope", 11.43, 0, 1000,
                   "the steepest receiver slope culling allows for: at least shadow.sun_resolve.max_slope")
      .param_int("tiles", 8, 1, kCascadeMaxTilesPerSide,
                 "tiles per side of a cascade: the unit of the static layers' refresh")
      .param_int("budget_triangles", 500000, 0, 1e9,
                 "static triangles shadow.cascades_static draws per frame at most, after a reset (a unit above it is "
                 "drawn alone)")
      .flag("cache", true,
            "1: the static layers (shadow.cascades_static) carry over from the previous frame and only the stale "
            "tiles the view needs are redrawn; 0: every static layer drawn whole each frame")
      .flag("light_occlusion", true,
            "1: drop casters wholly behind shadow.distant_occluders from the sun; 0: not (culling=0 turns every "
            "test off)")
      .flag("culling", true,
            "1: drop casters outside each cascade's volume or whose shadow is hidden (0 keeps them, for the tests)")
      .needs("sun_above_horizon")
      .run([](PassContext& ctx) { shadow_cull::ShadowCuller(ctx).run(); });
}

}  // namespace nightcap
