// How lighting.tiled divides the view into tiles and lays out its tile lists, for the pass, its
// shader (passes/lighting/tiled.comp) and the tests. A tile is 16×16 pixels, a quarter of a
// lights.cluster tile, so each of its pixels falls in the froxels of one cluster tile. Each tile
// gets a class:
//   0 (unlit): no pixel to shade (sky, or emissive-only surfaces): written as 0 when classified;
//   1 (directional): lit pixels, and no froxel they fall in lists a local light: the sun and
//     directional lights only;
//   2 (local): some pixel's froxel lists local lights, point and spot lights only;
//   3 (tube): some pixel's froxel lists a tube light, none a sphere;
//   4 (sphere): some pixel's froxel lists a sphere light, none a tube;
//   5 (sphere and tube): both kinds are listed in the tile.
// Classes 1 to 5 are shaded by one indirect dispatch each, a workgroup per listed tile; each is
// its own pipeline, which leaves out the code its tiles do not need. That matters on lavapipe,
// which runs a loop's body at least once per SIMD row even when no lane enters it: with spheres
// and tubes in one class, the 2 km map's street (no sphere light at all) paid for a pass of the
// sphere code in every row of every tile with a tube.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include "passes/core/buffer_schema.h"
#include "passes/lighting/tiled.glsl.h"

namespace nightcap {

// Tiles lighting.tile_lists holds: those of the largest output (16384² pixels).
constexpr uint32_t kLightingTileCapacity = 1u << 20;

enum class TileClass : uint32_t { unlit = 0, directional = 1, local = 2, tube = 3, sphere = 4, sphere_and_tube = 5 };

// GpuTileClasses and GpuTileEntry: passes/lighting/tiled.glsl.h.
static_assert(sizeof(GpuTileClasses) == 80);
static_assert(sizeof(GpuTileEntry) == 8);

BufferSchema tile_classes_schema();
BufferSchema tile_entry_schema();

}  // namespace nightcap
