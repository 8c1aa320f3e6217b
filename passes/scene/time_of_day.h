// Time of day [004 §2.3]: the sun (or, at night, the moon) for an hour of the day, and the
// table of `nightcap bake-tod`, which says for each instance of the built-in map at which of 12
// hours (every 2 h) it can cast a shadow anyone sees. shadow.cull drops a caster whose bit for
// the hour is clear; between baked hours it keeps those visible at either neighbour.
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "passes/scene/scene.h"

namespace nightcap {

// Night City lies on the coast of California; 37.8° N is the San Francisco Bay. The date is an
// equinox (the sun's declination 0) and the hour local apparent solar time, so the sun rises due
// east at 6:00, stands 52.2° up in the south at noon and sets due west at 18:00.
constexpr double kTodLatitudeDegrees = 37.8;
constexpr uint32_t kTodHours = 12;  // baked at 0:00, 2:00, … 22:00
constexpr double kTodHourStep = 24.0 / kTodHours;
constexpr uint16_t kTodAllHours = (1u << kTodHours) - 1;

// The unit vector toward the sun at `hour` (world: +x east, +y up, -z north, the map's axes).
glm::dvec3 sun_towards(double hour);
// The directional light at `hour`: the sun while it is above the horizon, else the full moon,
// which at an equinox stands opposite the sun (a simple model: the moon's orbit in the
// ecliptic, full at midnight). At 6:00 and 18:00 both lie on the horizon: the light is level
// and casts no shadow.
Light sky_light(double hour);
// Replaces the scene's first directional light (the one the shadow passes follow) with
// sky_light(hour), or puts it first when there is none. Throws SceneError for an hour outside
// [0, 24).
void set_hour(Scene& scene, double hour);

// The baked hours whose bits decide at `hour`: the hour's own bit when it is a baked one, else
// the two around it (their union: a caster visible at either is kept).
uint16_t tod_hour_bits(double hour);

struct TodBakeOptions {
  // Side of a texel of the ID render, metres. Coverage of the occluders is trusted only where a
  // texel and its 8 neighbours are covered, which is exact for occluders whose gaps are at least
  // a texel wide: the map's buildings stand at least 2 m apart.
  double texel_metres = 0.5;
  uint32_t threads = 0;  // 0: the machine's
};

struct TodTable {
  uint32_t seed = 0;
  double map_size_km = 0.0;
  std::string scene_hash;         // of the instance list the table is for (tod_scene_hash)
  std::vector<uint16_t> visible;  // per instance: bit k set when it can cast a visible shadow at 2k:00
};

// The content hash of what a table depends on: each instance's transform, mesh, material and
// motion, and the meshes' geometry.
std::string tod_scene_hash(const Scene& scene);

// Bakes the table of a built-in map (the scene of build_map({seed, size_km})).
TodTable bake_tod(const Scene& scene, uint32_t seed, double size_km, const TodBakeOptions& options = {});

// Writes the table atomically (a temporary file beside it, then a rename). Throws SceneError.
void write_tod(const TodTable& table, const std::filesystem::path& path);
// Reads a table and checks it against the scene it is for; throws SceneError naming the file and
// what is wrong (not a table, another version, truncated, corrupt, another map).
TodTable read_tod(const std::filesystem::path& path, uint32_t seed, double size_km, const Scene& scene);

}  // namespace nightcap
