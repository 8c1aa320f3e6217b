// The built-in map: a grid of 100 m blocks (84 m lots between 16 m streets) over a square of
// `size_km`, centred on the origin. Districts of varied density grow around centres drawn from
// the seed; between them lie badlands of bare ground. Built blocks carry a road tile and a
// sidewalk, buildings whose shells and roofs have three levels of detail, neon signs (emissive
// bars that are also tube lights), street lamps (point lights with hand-set ranges), trees
// (foliage stencil class), traffic driving along the streets and a few pedestrians made of
// rigid body, face and hair parts, and decals: projected ones (dashed lane markings, grime on
// the pavements, graffiti on the walls) and mesh ones (posters on the walls, puddles on the
// sidewalks). Meshes are shared: instances differ by transform and
// material. Everything derives from the seed through std::mt19937's raw output, so a seed gives
// the same map on every platform.
#include <algorithm>
#include <cmath>
#include <map>

#include "passes/scene/scene_kit.h"

namespace nightcap {

using namespace scene_kit;

namespace {

constexpr double kBlock = 100.0, kStreet = 16.0, kLot = kBlock - kStreet;
constexpr float kFloor = 4.0f;
// Where the levels of detail switch, in metres from the camera to the mesh's centre.
constexpr float kLod0Distance = 150.0f, kLod1Distance = 600.0f;

constexpr int kFootprints[] = {16, 24, 32, 40};
constexpr int kHeights[] = {12, 20, 32, 48, 72, 100, 140, 200};

struct District {
  glm::dvec2 centre;
  double radius, peak;  // peak density at the centre, falling off as a Gaussian
};

struct Meshes {
  std::map<std::pair<int, int>, uint32_t> shell, roof;  // by (footprint index, height index)
  uint32_t road, sidewalk, ground, pole, car, trunk, canopy, body, face, hair, sign_h, sign_v;
};

// Links the levels: level k is drawn up to distances[k] metres, the last one up to
// `draw_distance`.
void chain(Scene& scene, const std::vector<uint32_t>& levels, const std::vector<float>& distances,
           float draw_distance = INFINITY) {
  for (size_t k = 0; k + 1 < levels.size(); ++k) {
    scene.primitives[levels[k]].coarser = int32_t(levels[k + 1]);
    scene.primitives[levels[k]].lod_distance = distances[k];
  }
  scene.primitives[levels.back()].draw_distance = draw_distance;
}

// A building's footprint as placed: walls at `half` metres from `base` along ±x and ±z.
struct Building {
  glm::dvec3 base;
  double half, height;
};

// A projected decal's box: `size` metres along its local x, y, z, centred on `centre`, its local
// z along `facing` and its local y along `up` (a unit vector perpendicular to `facing`).
glm::dmat4 decal_box(glm::dvec3 centre, glm::dvec3 facing, glm::dvec3 up, glm::dvec3 size) {
  const glm::dvec3 x = glm::cross(up, facing);
  return glm::dmat4(glm::dvec4(x * size.x, 0.0), glm::dvec4(up * size.y, 0.0), glm::dvec4(facing * size.z, 0.0),
                    glm::dvec4(centre, 1.0));
}

// How far small props stay drawn, in metres: beyond, they cover about a pixel or less at 720p.
constexpr float kPropDistance = 400.0f, kSignDistance = 1500.0f, kCarDistance = 600.0f, kPersonDistance = 250.0f,
                kTreeDistance = 1200.0f;

// A shell: the body's four sides, and (finer levels) a ledge ring every `ledge_every` metres.
uint32_t shell_level(Builder& build, uint32_t material, float w, float h, float d, float ledge_every) {
  build.begin(material);
  // The body first: its four walls are what the occlusion buffer takes.
  build.add_box({0, h / 2, 0}, {w / 2, h / 2, d / 2}, 1.0f / 16.0f, false);
  const uint32_t body_indices = uint32_t(build.scene().indices.size());
  if (ledge_every > 0)
    for (float y = ledge_every; y < h - 1.0f; y += ledge_every) {
      const float out = 0.25f, t = 0.15f;
      build.add_box({0, y, d / 2 + out / 2}, {w / 2 + out, t, out / 2}, 1.0f / 16.0f, true, true);
      build.add_box({0, y, -d / 2 - out / 2}, {w / 2 + out, t, out / 2}, 1.0f / 16.0f, true, true);
      build.add_box({w / 2 + out / 2, y, 0}, {out / 2, t, d / 2}, 1.0f / 16.0f, true, true);
      build.add_box({-w / 2 - out / 2, y, 0}, {out / 2, t, d / 2}, 1.0f / 16.0f, true, true);
    }
  const uint32_t shell = build.end();
  Primitive& p = build.scene().primitives[shell];
  p.occluder_index_count = body_indices - p.first_index;
  return shell;
}

uint32_t roof_level(Builder& build, uint32_t material, float w, float d, int detail) {
  build.begin(material);
  build.add_box({0, 0.1f, 0}, {w / 2, 0.1f, d / 2}, 0.25f);
  const uint32_t cap_indices = uint32_t(build.scene().indices.size());
  if (detail >= 1) {
    const float p = 0.2f, ph = 0.6f;
    build.add_box({0, 0.2f + ph / 2, d / 2 - p / 2}, {w / 2, ph / 2, p / 2}, 0.25f);
    build.add_box({0, 0.2f + ph / 2, -d / 2 + p / 2}, {w / 2, ph / 2, p / 2}, 0.25f);
    build.add_box({w / 2 - p / 2, 0.2f + ph / 2, 0}, {p / 2, ph / 2, d / 2 - p}, 0.25f);
    build.add_box({-w / 2 + p / 2, 0.2f + ph / 2, 0}, {p / 2, ph / 2, d / 2 - p}, 0.25f);
  }
  if (detail >= 2) {
    build.add_box({w / 4, 0.2f + 0.9f, d / 5}, {1.2f, 0.9f, 1.5f}, 0.25f);
    build.add_box({-w / 5, 0.2f + 0.7f, -d / 4}, {1.5f, 0.7f, 1.0f}, 0.25f);
  }
  const uint32_t roof = build.end();
  Primitive& p = build.scene().primitives[roof];
  p.occluder_index_count = cap_indices - p.first_index;  // the cap alone
  return roof;
}

Meshes make_meshes(Builder& build, uint32_t facade, uint32_t roof, uint32_t road, uint32_t sidewalk, uint32_t ground,
                   uint32_t pole, uint32_t paint, uint32_t bark, uint32_t leaves, uint32_t skin, uint32_t face,
                   uint32_t hair, uint32_t neon) {
  Meshes m;
  Scene& scene = build.scene();
  for (int f = 0; f < 4; ++f) {
    const float w = float(kFootprints[f]);
    for (int hi = 0; hi < 8; ++hi) {
      const float h = float(kHeights[hi]);
      // A ledge at every floor up close, a few far away, none at the last level.
      const uint32_t l0 = shell_level(build, facade, w, h, w, kFloor);
      const uint32_t l1 = shell_level(build, facade, w, h, w, std::min(6 * kFloor, h / 2));
      const uint32_t l2 = shell_level(build, facade, w, h, w, 0.0f);
      chain(scene, {l0, l1, l2}, {kLod0Distance, kLod1Distance});
      m.shell[{f, hi}] = l0;
    }
    const uint32_t r0 = roof_level(build, roof, w, w, 2), r1 = roof_level(build, roof, w, w, 1),
                   r2 = roof_level(build, roof, w, w, 0);
    chain(scene, {r0, r1, r2}, {kLod0Distance, kLod1Distance});
    m.roof[{f, 0}] = r0;
  }
  // Roads and sidewalks are tiles of one block; a block's road tile covers its lot too, under
  // the sidewalk slab.
  m.road = build.box({float(kBlock / 2), 0.05f, float(kBlock / 2)}, road, 0.25f);
  m.sidewalk = build.box({float(kLot / 2 + 2), 0.075f, float(kLot / 2 + 2)}, sidewalk, 0.5f);
  m.ground = build.box({200.0f, 0.05f, 200.0f}, ground, 0.05f);
  m.pole = build.box({0.08f, 3.0f, 0.08f}, pole, 1.0f);
  scene.primitives[m.pole].draw_distance = kPropDistance;
  build.begin(paint);
  build.add_box({0, 0.75f, 0}, {2.25f, 0.55f, 0.95f}, 1.0f);
  build.add_box({-0.2f, 1.65f, 0}, {1.2f, 0.35f, 0.85f}, 1.0f);
  m.car = build.end();
  scene.primitives[m.car].draw_distance = kCarDistance;
  m.trunk = build.box({0.2f, 2.0f, 0.2f}, bark, 1.0f);
  scene.primitives[m.trunk].draw_distance = kPropDistance;
  // Canopies: a cluster of boxes up close, one box far away.
  build.begin(leaves);
  build.add_box({0, 0, 0}, {1.8f, 1.4f, 1.8f}, 0.5f, true, true);
  build.add_box({0.9f, 0.8f, 0.4f}, {1.0f, 1.0f, 1.0f}, 0.5f, true, true);
  build.add_box({-0.8f, 0.6f, -0.6f}, {1.1f, 0.9f, 1.0f}, 0.5f, true, true);
  const uint32_t canopy0 = build.end();
  const uint32_t canopy1 = build.box({2.0f, 1.8f, 2.0f}, leaves, 0.5f, true, true);
  chain(scene, {canopy0, canopy1}, {kLod0Distance}, kTreeDistance);
  m.canopy = canopy0;
  build.begin(skin);
  build.add_box({0, 0.45f, 0}, {0.18f, 0.45f, 0.12f}, 1.0f);  // legs
  build.add_box({0, 1.2f, 0}, {0.25f, 0.3f, 0.14f}, 1.0f);    // torso
  m.body = build.end();
  m.face = build.box({0.11f, 0.13f, 0.11f}, face, 1.0f, true, true);
  m.hair = build.box({0.12f, 0.05f, 0.12f}, hair, 1.0f, true, true);
  for (uint32_t part : {m.body, m.face, m.hair}) scene.primitives[part].draw_distance = kPersonDistance;
  m.sign_h = build.box({2.5f, 0.06f, 0.06f}, neon, 1.0f, true, true);
  m.sign_v = build.box({0.06f, 2.0f, 0.06f}, neon, 1.0f, true, true);
  for (uint32_t sign : {m.sign_h, m.sign_v}) scene.primitives[sign].draw_distance = kSignDistance;
  return m;
}

// Decals along each built block, from their own random sequence so the rest of the map does not
// change with them: a dashed marking down the middle of the street on the block's +z side, grime
// on the pavement there, graffiti and a poster on building walls, puddles on the sidewalk.
void add_decals(Builder& build, uint32_t seed, const std::vector<glm::dvec2>& blocks,
                const std::vector<std::vector<Building>>& buildings) {
  Scene& scene = build.scene();
  Random random(seed * 2246822519u + 3266489917u);
  const uint32_t poster_paper = build.material([] {
    Material m = plain("decal.poster", {0.8f, 0.75f, 0.65f}, 0.0f, 0.7f, stencil::plain);
    m.base_color.a = 0.9f;
    m.decal = true;
    return m;
  }());
  const uint32_t puddle_water = build.material([] {
    Material m = plain("decal.puddle", {0.02f, 0.02f, 0.025f}, 0.0f, 0.05f, stencil::plain);
    m.base_color.a = 0.7f;
    m.decal = true;
    return m;
  }());
  // Thin slabs: a poster 1 cm thick, a puddle 8 mm (drawn with a depth bias over what it lies on).
  const uint32_t poster = build.box({0.6f, 0.85f, 0.005f}, poster_paper, 1.0f);
  const uint32_t puddle = build.box({1.0f, 0.004f, 0.6f}, puddle_water, 1.0f);
  for (uint32_t mesh : {poster, puddle}) scene.primitives[mesh].draw_distance = kPropDistance;
  const glm::dvec3 up(0, 1, 0), north(0, 0, -1);
  for (size_t b = 0; b < blocks.size(); ++b) {
    const glm::dvec2 c = blocks[b];
    Decal lane;
    lane.world = decal_box({c.x, 0.0, c.y + kBlock / 2}, up, north, {kBlock, 0.15, 0.4});
    lane.pattern = DecalPattern::stripes;
    lane.albedo = {0.8f, 0.78f, 0.7f};
    lane.opacity = 0.9f;
    lane.roughness = 0.6f;
    lane.scale = 25.0f;
    lane.draw_distance = 600.0f;
    scene.decals.push_back(lane);
    const int grime_patches = 1 + int(random.below(2));
    for (int k = 0; k < grime_patches; ++k) {
      const double turn = random.range(0.0, glm::two_pi<double>());
      const glm::dvec3 at{c.x + random.range(-45.0, 45.0), 0.0,
                          c.y + random.range(40.0, 48.0)};  // braced: drawn in order
      Decal grime;
      grime.world = decal_box(at, up, {std::sin(turn), 0.0, std::cos(turn)},
                              {random.range(3.0, 6.0), random.range(3.0, 6.0), 1.0});
      grime.pattern = DecalPattern::grime;
      grime.albedo = {0.05f, 0.04f, 0.03f};
      grime.opacity = 0.85f;
      grime.roughness = 0.9f;
      grime.scale = 4.0f;
      grime.draw_distance = 300.0f;
      scene.decals.push_back(grime);
    }
    const glm::dvec2 puddle_draw{random.range(-40.0, 40.0), random.uniform()};
    if (puddle_draw.y < 0.6) {
      // Lying on the sidewalk slab (its top at 0.15 m): coplanar with it underneath.
      build.place(puddle, {c.x + puddle_draw.x, 0.154, c.y + 42.5}, random.range(-0.3, 0.3));
    }
    if (buildings[b].empty()) continue;
    for (int k = 0; k < 2; ++k) {
      const Building& at = buildings[b][random.below(uint32_t(buildings[b].size()))];
      const int side = int(random.below(4));
      const glm::dvec3 facing = side == 0   ? glm::dvec3(1, 0, 0)
                                : side == 1 ? glm::dvec3(-1, 0, 0)
                                : side == 2 ? glm::dvec3(0, 0, 1)
                                            : glm::dvec3(0, 0, -1);
      const glm::dvec3 along(facing.z, 0.0, -facing.x);
      const double offset = random.range(-at.half + 3.0, at.half - 3.0), height = random.range(1.5, 3.5);
      const glm::dvec3 wall = at.base + facing * at.half + along * offset + glm::dvec3(0, height, 0);
      if (k == 0) {
        Decal graffiti;
        graffiti.world = decal_box(wall, facing, up, {random.range(3.0, 6.0), random.range(1.5, 2.5), 1.0});
        graffiti.pattern = DecalPattern::grime;
        graffiti.albedo = kNeon[random.below(uint32_t(kNeon.size()))];
        graffiti.opacity = 1.0f;
        graffiti.roughness = 0.4f;
        graffiti.scale = 3.0f;
        graffiti.normal_weight = 0.3f;
        graffiti.draw_distance = 300.0f;
        scene.decals.push_back(graffiti);
      } else {
        build.place(poster, wall + facing * 0.006, std::atan2(facing.x, facing.z));
      }
    }
  }
}

}  // namespace

Shot parse_shot(const std::string& name) {
  if (name == "street") return Shot::street;
  if (name == "rooftop") return Shot::rooftop;
  if (name == "aerial") return Shot::aerial;
  throw SceneError("--shot '" + name + "': expected street, rooftop or aerial");
}

std::string shot_name(Shot shot) {
  return shot == Shot::street ? "street" : shot == Shot::rooftop ? "rooftop" : "aerial";
}

Scene build_map(const MapOptions& options) {
  if (!(options.size_km >= 0.5 && options.size_km <= 16.0))
    throw SceneError("--map-size " + std::to_string(options.size_km) + ": expected 0.5 to 16 km");
  Scene scene;
  char size[32];
  std::snprintf(size, sizeof(size), "%g", options.size_km);
  scene.source =
      "built-in map (seed " + std::to_string(options.seed) + ", " + size + " km, " + shot_name(options.shot) + " shot)";
  Random random(options.seed);
  Builder build(scene);

  const std::vector<uint32_t> facades = facade_materials(random, build);
  const uint32_t roof = build.material(plain("roof", {0.12f, 0.12f, 0.13f}, 0.0f, 0.8f, stencil::plain));
  const uint32_t road = build.material(plain("road.wet_asphalt", {0.05f, 0.05f, 0.055f}, 0.0f, 0.25f, stencil::road));
  const uint32_t sidewalk = build.material(plain("sidewalk", {0.22f, 0.21f, 0.2f}, 0.0f, 0.7f, stencil::plain));
  const uint32_t ground = build.material(plain("badlands", {0.18f, 0.14f, 0.1f}, 0.0f, 0.9f, stencil::plain));
  const uint32_t pole = build.material(plain("lamp.pole", {0.3f, 0.3f, 0.32f}, 1.0f, 0.4f, stencil::plain));
  const uint32_t bark = build.material(plain("tree.bark", {0.1f, 0.07f, 0.05f}, 0.0f, 0.9f, stencil::plain));
  const uint32_t leaves = build.material(plain("tree.leaves", {0.05f, 0.16f, 0.06f}, 0.0f, 0.8f, stencil::foliage));
  const uint32_t skin = build.material(plain("character.body", {0.25f, 0.2f, 0.3f}, 0.0f, 0.6f, stencil::body));
  const uint32_t face = build.material(plain("character.face", {0.6f, 0.42f, 0.33f}, 0.0f, 0.5f, stencil::face));
  const uint32_t hair = build.material(plain("character.hair", {0.08f, 0.05f, 0.04f}, 0.0f, 0.45f, stencil::hair));
  std::vector<uint32_t> paints, neons;
  for (const glm::vec3& colour : kNeon) {
    paints.push_back(
        build.material(plain("car.paint", colour * 0.5f + glm::vec3(0.05f), 0.9f, 0.25f, stencil::vehicle)));
    Material neon = plain("neon", colour * 0.2f, 0.0f, 0.3f, stencil::plain);
    neon.emissive = colour;
    neon.emissive_strength = 40.0f;
    neons.push_back(build.material(neon));
  }
  const Meshes mesh = make_meshes(build, facades[0], roof, road, sidewalk, ground, pole, paints[0], bark, leaves, skin,
                                  face, hair, neons[0]);

  // Districts: a dense core and a handful of others; the rest of the map is badlands.
  const double half_map = options.size_km * 500.0;
  std::vector<District> districts;
  const int district_count = std::max(2, int(std::lround(options.size_km * options.size_km / 16.0)));
  for (int k = 0; k < district_count; ++k)
    districts.push_back({{random.range(-half_map, half_map), random.range(-half_map, half_map)},
                         random.range(500.0, 1500.0) * std::min(1.0, options.size_km / 4.0),
                         k == 0 ? 1.0 : random.range(0.55, 0.95)});
  auto density = [&](glm::dvec2 p) {
    double d = 0.0;
    for (const District& district : districts) {
      const glm::dvec2 v = (p - district.centre) / district.radius;
      d = std::max(d, district.peak * std::exp(-glm::dot(v, v)));
    }
    return d;
  };

  // Bare ground everywhere, in 400 m tiles just below the streets.
  const int tiles = std::max(1, int(std::ceil(options.size_km * 1000.0 / 400.0)));
  for (int x = 0; x < tiles; ++x)
    for (int z = 0; z < tiles; ++z)
      build.place(mesh.ground, {-half_map + 200.0 + 400.0 * x, -0.12, -half_map + 200.0 + 400.0 * z});

  const int blocks = int(options.size_km * 1000.0 / kBlock);
  const double origin = -blocks * kBlock / 2;
  struct BuiltBlock {
    glm::dvec2 centre;
    double density;
    double tallest;
  };
  std::vector<BuiltBlock> built;
  std::vector<std::vector<Building>> buildings;  // per built block, for its decals
  for (int bx = 0; bx < blocks; ++bx)
    for (int bz = 0; bz < blocks; ++bz) {
      const glm::dvec2 c(origin + (bx + 0.5) * kBlock, origin + (bz + 0.5) * kBlock);
      const double rho = density(c);
      const double chance = random.uniform();
      if (rho < 0.12 || chance > 0.35 + rho) continue;
      build.place(mesh.road, {c.x, -0.05, c.y});
      build.place(mesh.sidewalk, {c.x, 0.075, c.y});
      double tallest = 0.0;
      buildings.emplace_back();
      // Buildings on a 2×2 grid of the lot, the densest blocks full, taller toward a core.
      for (int q = 0; q < 4; ++q) {
        const double draw = random.uniform(), height_draw = random.uniform(), footprint_draw = random.uniform(),
                     facade_draw = random.uniform(), turn = random.uniform();
        if (draw > 0.25 + rho) continue;
        const int f = std::min(3, int(footprint_draw * 4));
        const int hi = std::clamp(int(height_draw * 3 + rho * 6), 0, 7);
        const double ox = (q & 1 ? 1 : -1) * kLot / 4, oz = (q & 2 ? 1 : -1) * kLot / 4;
        const glm::dvec3 base(c.x + ox, 0.15, c.y + oz);
        const double yaw = glm::half_pi<double>() * std::floor(turn * 4);
        build.place(mesh.shell.at({f, hi}), base, yaw).material = int32_t(facades[std::min(2, int(facade_draw * 3))]);
        build.place(mesh.roof.at({f, 0}), base + glm::dvec3(0, kHeights[hi], 0), yaw);
        tallest = std::max(tallest, double(kHeights[hi]));
        buildings.back().push_back({base, kFootprints[f] / 2.0, double(kHeights[hi])});
        // Neon on the facades, more of it downtown: a bar and its tube light.
        const int signs = int(random.uniform() * (1 + 7 * rho));
        const double w = kFootprints[f] / 2.0;
        for (int s = 0; s < signs; ++s) {
          const uint32_t colour = random.below(uint32_t(kNeon.size()));
          const bool vertical = random.uniform() < 0.4;
          const int side = int(random.below(4));
          const double y = random.range(3.0, std::min(double(kHeights[hi]) - 2.0, 24.0));
          const glm::dvec3 normal = side == 0   ? glm::dvec3(1, 0, 0)
                                    : side == 1 ? glm::dvec3(-1, 0, 0)
                                    : side == 2 ? glm::dvec3(0, 0, 1)
                                                : glm::dvec3(0, 0, -1);
          const glm::dvec3 mid = glm::dvec3(base.x, y, base.z) + normal * (w + 0.35);
          const double sign_yaw = std::abs(normal.x) > 0 ? glm::half_pi<double>() : 0.0;
          build.place(vertical ? mesh.sign_v : mesh.sign_h, mid, sign_yaw).material = int32_t(neons[colour]);
          const glm::dvec3 along = vertical ? glm::dvec3(0, 1, 0) : glm::dvec3(normal.z, 0, normal.x);
          const double length = vertical ? 4.0 : 5.0;
          scene.lights.push_back(
              neon_tube(mid - along * (length / 2), mid + along * (length / 2), kNeon[colour], 30.0f));
        }
      }
      // A reflection probe in the street along the block's +z side (where the street shot stands):
      // 3 m up its middle, its box the street between the lots (kStreet wide), the block long and
      // the block's tallest building high (12 m at least).
      scene.probes.push_back({glm::dvec3(c.x, 3.0, c.y + kBlock / 2),
                              glm::dvec3(c.x - kBlock / 2, 0.0, c.y + kLot / 2),
                              glm::dvec3(c.x + kBlock / 2, std::max(tallest, 12.0), c.y + kBlock - kLot / 2)});
      // Street lamps on the four kerbs, each a pole and a point light with a hand-set range.
      for (int side = 0; side < 4; ++side) {
        const glm::dvec2 kerb = side == 0   ? glm::dvec2(kLot / 2 + 1.0, 0)
                                : side == 1 ? glm::dvec2(-kLot / 2 - 1.0, 0)
                                : side == 2 ? glm::dvec2(0, kLot / 2 + 1.0)
                                            : glm::dvec2(0, -kLot / 2 - 1.0);
        const glm::dvec3 foot(c.x + kerb.x, 0.0, c.y + kerb.y);
        build.place(mesh.pole, foot + glm::dvec3(0, 3.0, 0));
        scene.lights.push_back(street_lamp(foot + glm::dvec3(0, 6.2, 0), 30.0f));
      }
      // Trees where the city thins out.
      const int trees = int(random.uniform() * 4 * (1.0 - rho));
      for (int t = 0; t < trees; ++t) {
        const glm::dvec3 foot(c.x + random.range(-kLot / 2, kLot / 2), 0.15, c.y + (kLot / 2 - 1.5));
        build.place(mesh.trunk, foot + glm::dvec3(0, 2.0, 0));
        build.place(mesh.canopy, foot + glm::dvec3(0, 5.2, 0), random.range(0, 6.28));
      }
      // Traffic in the street along the block's +z side, driving either way.
      const int cars = int(random.uniform() * 3 * rho);
      for (int k = 0; k < cars; ++k) {
        const double dir = random.uniform() < 0.5 ? 1.0 : -1.0, speed = random.range(6.0, 14.0);
        const glm::dvec3 at(c.x + random.range(-kBlock / 2, kBlock / 2), 0.0, c.y + kBlock / 2 - dir * 3.5);
        Instance& car = build.place(mesh.car, at, dir > 0 ? 0.0 : glm::pi<double>());
        car.material = int32_t(paints[random.below(uint32_t(paints.size()))]);
        car.moving = true;
        car.velocity = glm::vec3(float(dir * speed), 0.0f, 0.0f);
      }
      // Pedestrians on the sidewalk along the same street, walking either way.
      const int people = random.uniform() < rho * 0.8 ? 1 + int(random.below(3)) : 0;
      for (int k = 0; k < people; ++k) {
        const double dir = random.uniform() < 0.5 ? 1.0 : -1.0;
        const glm::dvec3 at(c.x + random.range(-kLot / 2, kLot / 2), 0.15, c.y + kLot / 2 + 1.0);
        const double yaw = dir > 0 ? -glm::half_pi<double>() : glm::half_pi<double>();
        const glm::vec3 walk(float(dir * 1.3), 0.0f, 0.0f);
        for (const auto& [part, offset] : {std::pair{mesh.body, 0.0}, {mesh.face, 1.63}, {mesh.hair, 1.8}}) {
          Instance& i = build.place(part, at + glm::dvec3(0, offset, 0), yaw);
          i.moving = true;
          i.velocity = walk;
        }
      }
      built.push_back({c, rho, tallest});
    }

  std::vector<glm::dvec2> centres;
  for (const BuiltBlock& b : built) centres.push_back(b.centre);
  add_decals(build, options.seed, centres, buildings);
  scene.lights.push_back(moon());

  // The shot: its place drawn from the seed among every built block of the map (the dense
  // downtown blocks for the street), so any corner can hold it.
  Camera camera;
  camera.yfov = glm::radians(60.0f);
  if (built.empty()) {
    camera.world = glm::inverse(glm::lookAt(glm::dvec3(0, 50, 0), glm::dvec3(100, 0, 100), glm::dvec3(0, 1, 0)));
  } else {
    std::vector<const BuiltBlock*> pool;
    for (const BuiltBlock& b : built)
      if (options.shot != Shot::street || b.density >= 0.75) pool.push_back(&b);
    if (pool.empty())
      for (const BuiltBlock& b : built) pool.push_back(&b);
    Random pick(options.seed * 2654435761u + uint32_t(options.shot));
    const BuiltBlock& at = *pool[pick.below(uint32_t(pool.size()))];
    // Along the street on the block's +z side, where its traffic and pedestrians are, either way
    // (the street shot); the other shots face any of the four directions.
    const int heading = int(pick.below(options.shot == Shot::street ? 2 : 4));
    const glm::dvec3 forward = heading == 0   ? glm::dvec3(1, 0, 0)
                               : heading == 1 ? glm::dvec3(-1, 0, 0)
                               : heading == 2 ? glm::dvec3(0, 0, 1)
                                              : glm::dvec3(0, 0, -1);
    const glm::dvec3 side = options.shot == Shot::street ? glm::dvec3(0, 0, 1) : glm::dvec3(-forward.z, 0, forward.x);
    const glm::dvec3 block(at.centre.x, 0.0, at.centre.y);
    glm::dvec3 eye, target;
    if (options.shot == Shot::street) {
      // In the street beside the block, on the pavement edge, looking down the street.
      eye = block + side * (kBlock / 2 - 5.0) + glm::dvec3(0, 1.7, 0);
      target = eye + forward * 100.0 + glm::dvec3(0, 4.0, 0);
      camera.znear = 0.1f;
    } else if (options.shot == Shot::rooftop) {
      eye = block + side * (kBlock / 2) + glm::dvec3(0, 60.0, 0);
      target = eye + forward * 1000.0 + glm::dvec3(0, -40.0, 0);
      camera.znear = 0.5f;
    } else {
      eye = block - forward * 800.0 + glm::dvec3(0, 800.0, 0);
      target = block;
      camera.znear = 2.0f;
    }
    camera.world = glm::inverse(glm::lookAt(eye, target, glm::dvec3(0, 1, 0)));
  }
  scene.camera = camera;
  return scene;
}

}  // namespace nightcap
