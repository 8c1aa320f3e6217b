// The bake [004 §2.3]: the map is cut into 256 m sectors; for each sector and each baked hour,
// the occluders of the sector and its 8 neighbours are rasterised on the CPU into a depth buffer
// seen from the light (orthographic along its rays, 0.5 m texels), and each caster of the sector
// is visible when some part of it is not behind that depth. A caster hidden everywhere is behind
// others from the light's side, so every shadow it casts lies inside theirs and the shadow map
// stores their depth wherever it would have stored its own: dropping it changes no texel.
//
// The seed renders object IDs and keeps what survives the depth test. Sampled at texel centres
// that loses a small caster between samples that the runtime's finer cascades do see, so the
// test here is conservative on both sides instead:
// - the caster's triangles are rasterised conservatively (every texel they touch), at the least
//   depth they reach in it;
// - an occluder's depth counts at a texel only where its sample and its 8 neighbours' are
//   covered, and then as the farthest of those 9: on a plane that bounds the depth everywhere
//   in the texel, and coverage of 3×3 samples means coverage of the texel when the occluders'
//   gaps are at least a texel wide.
// Occluders are what every frame surely draws into the cascades: static opaque instances whose
// levels of detail are all drawn at any distance and share their occluder prefix (the map's
// building bodies, roof caps, roads, sidewalks and ground), and of those only that prefix. A
// moving caster is never hidden (it moves) and hides nothing.
#include "passes/scene/time_of_day.h"

#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <thread>

#include "passes/core/hash.h"
#include "passes/scene/scene_kit.h"
#include "passes/scene/shadow_occluder.h"

namespace nightcap {

glm::dvec3 sun_towards(double hour) {
  // Hour angle: 15° an hour from solar noon. With declination 0 the sun's direction in the local
  // (east, north, up) frame is (-sin H, -sin φ cos H, cos φ cos H).
  const double h = glm::radians(15.0 * (hour - 12.0)), phi = glm::radians(kTodLatitudeDegrees);
  const glm::dvec3 east_north_up(-std::sin(h), -std::sin(phi) * std::cos(h), std::cos(phi) * std::cos(h));
  glm::dvec3 world(east_north_up.x, east_north_up.z, -east_north_up.y);
  // cos(±90°) is 6e-17, not 0: at sunrise and sunset the light is exactly level.
  if (std::abs(world.y) < 1e-9) world.y = 0.0;
  return world;
}

Light sky_light(double hour) {
  const glm::dvec3 to_sun = sun_towards(hour);
  Light light = scene_kit::moon();
  if (to_sun.y > 0.0) {
    light.direction = glm::vec3(-to_sun);
    light.color = {1.0f, 0.95f, 0.88f};
    // 2% of real sunlight: the frame has no sky light, so the shadowed majority of the view sets
    // the exposure, and at 10 000 lux sunlit facades burnt out to white; at 2 000 the windows
    // still show on most of them.
    light.intensity = 2000.0f;
  } else {
    light.direction = glm::vec3(to_sun);  // the moon stands opposite the sun
  }
  return light;
}

void set_hour(Scene& scene, double hour) {
  if (!(hour >= 0.0 && hour < 24.0))
    throw SceneError("--hour " + std::to_string(hour) + ": expected hours from 0 to 24 (24 excluded)");
  for (Light& light : scene.lights)
    if (light.type == LightType::directional) {
      light = sky_light(hour);
      return;
    }
  scene.lights.insert(scene.lights.begin(), sky_light(hour));
}

uint16_t tod_hour_bits(double hour) {
  const double slot = hour / kTodHourStep;
  const uint32_t below = uint32_t(std::floor(slot)) % kTodHours;
  if (slot == std::floor(slot)) return uint16_t(1u << below);
  return uint16_t(1u << below | 1u << (below + 1) % kTodHours);
}

namespace {

constexpr double kSector = 256.0;
// Depth (metres along the light's rays) by which a caster may lie behind the occluders' depth and
// still count as visible: the GPU's positions are quantised to 1/65535 of a mesh's box (3 mm
// for a 200 m building, 6 mm for a 400 m ground tile).
constexpr double kDepthSlack = 0.02;

// Affine object → light transform: rows give (u, v, depth) in metres.
struct LightTransform {
  glm::dvec3 row[3];
  double offset[3];
  glm::dvec3 apply(const glm::dvec3& p) const {
    return {glm::dot(row[0], p) + offset[0], glm::dot(row[1], p) + offset[1], glm::dot(row[2], p) + offset[2]};
  }
};

struct Basis {
  glm::dvec3 axis[3];  // u, v, and the light's travel
};

Basis light_basis(const glm::dvec3& travel) {
  const glm::dvec3 helper = std::abs(travel.y) > 0.99 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, travel));
  return {{u, glm::cross(travel, u), travel}};
}

struct Item {
  uint32_t instance;
  std::vector<uint32_t> levels;  // coarsest first: a coarse level decides most casters in a few triangles
  glm::dvec3 lo, hi;             // world box of every level
  bool occluder = false;
  uint32_t occluder_indices = 0;  // the finest level's prefix, when an occluder
};

// A depth buffer over the light-space rectangle of one window.
class LightRaster {
 public:
  LightRaster(const Basis& basis, const glm::dvec3& lo, const glm::dvec3& hi, double texel) : basis_(basis) {
    texel_ = texel;
    glm::dvec3 min(INFINITY), max(-INFINITY);
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 p(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
      for (int a = 0; a < 3; ++a) {
        min[a] = std::min(min[a], glm::dot(basis.axis[a], p));
        max[a] = std::max(max[a], glm::dot(basis.axis[a], p));
      }
    }
    origin_ = min;
    width_ = uint32_t(std::ceil((max.x - min.x) / texel)) + 1;
    height_ = uint32_t(std::ceil((max.y - min.y) / texel)) + 1;
    depth_.assign(size_t(width_) * height_, INFINITY);
  }

  // Texel units for u and v, metres from the window's nearest point for depth.
  LightTransform transform(const glm::dmat4& world) const {
    LightTransform t;
    for (int a = 0; a < 3; ++a) {
      const double scale = a < 2 ? 1.0 / texel_ : 1.0;
      for (int c = 0; c < 3; ++c) t.row[a][c] = glm::dot(basis_.axis[a], glm::dvec3(world[c])) * scale;
      t.offset[a] = (glm::dot(basis_.axis[a], glm::dvec3(world[3])) - origin_[a]) * scale;
    }
    return t;
  }

  // An occluder's triangle, sampled at texel centres (nearest depth kept).
  void occlude(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(area) < 1e-12) return;  // edge-on: it covers no sample
    const int x0 = std::max(0, int(std::ceil(std::min({a.x, b.x, c.x}) - 0.5)));
    const int x1 = std::min(int(width_) - 1, int(std::floor(std::max({a.x, b.x, c.x}) - 0.5)));
    const int y0 = std::max(0, int(std::ceil(std::min({a.y, b.y, c.y}) - 0.5)));
    const int y1 = std::min(int(height_) - 1, int(std::floor(std::max({a.y, b.y, c.y}) - 0.5)));
    const double inv = 1.0 / area;
    for (int y = y0; y <= y1; ++y) {
      const double py = y + 0.5;
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5;
        const double w0 = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) * inv;
        const double w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv;
        const double w2 = 1.0 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        float& d = depth_[size_t(y) * width_ + x];
        d = std::min(d, float(w0 * a.z + w1 * b.z + w2 * c.z));
      }
    }
  }

  // Each texel becomes the farthest of its 3×3 block (infinite where any sample is uncovered):
  // separable, rows then columns.
  void settle() {
    std::vector<float> rows(depth_.size());
    for (uint32_t y = 0; y < height_; ++y)
      for (uint32_t x = 0; x < width_; ++x) {
        const size_t i = size_t(y) * width_ + x;
        float m = depth_[i];
        m = std::max(m, x > 0 ? depth_[i - 1] : INFINITY);
        m = std::max(m, x + 1 < width_ ? depth_[i + 1] : INFINITY);
        rows[i] = m;
      }
    for (uint32_t y = 0; y < height_; ++y)
      for (uint32_t x = 0; x < width_; ++x) {
        const size_t i = size_t(y) * width_ + x;
        float m = rows[i];
        m = std::max(m, y > 0 ? rows[i - width_] : INFINITY);
        m = std::max(m, y + 1 < height_ ? rows[i + width_] : INFINITY);
        depth_[i] = m;
      }
  }

  // Whether some texel of the rectangle holds no occluder nearer than `nearest` (texel units,
  // metres): false proves everything in it hidden.
  bool rectangle_open(double u0, double u1, double v0, double v1, double nearest) const {
    if (u0 < 0 || v0 < 0 || u1 >= width_ || v1 >= height_) return true;
    for (int y = int(v0); y <= int(v1); ++y)
      for (int x = int(u0); x <= int(u1); ++x)
        if (nearest <= depth_[size_t(y) * width_ + x] + kDepthSlack) return true;
    return false;
  }

  // Whether some texel the triangle touches holds no occluder nearer than the triangle there.
  bool triangle_visible(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) const {
    const double u0 = std::min({a.x, b.x, c.x}), u1 = std::max({a.x, b.x, c.x});
    const double v0 = std::min({a.y, b.y, c.y}), v1 = std::max({a.y, b.y, c.y});
    if (u0 < 0 || v0 < 0 || u1 >= width_ || v1 >= height_) return true;  // beyond the occluders rasterised
    const double nearest = std::min({a.z, b.z, c.z});
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    // Edge-on (or tiny): every texel of its bounds at its nearest depth.
    if (std::abs(area) < 1e-9) return rectangle_open(u0, u1, v0, v1, nearest);
    // Edges as inside-positive lines, and the plane's depth gradient, per texel.
    const double s = area > 0 ? 1.0 : -1.0;
    const glm::dvec3* p[3] = {&a, &b, &c};
    double ex[3], ey[3], ec[3];
    for (int e = 0; e < 3; ++e) {
      const glm::dvec3 &from = *p[e], &to = *p[(e + 1) % 3];
      ex[e] = -(to.y - from.y) * s;
      ey[e] = (to.x - from.x) * s;
      ec[e] = -(ex[e] * from.x + ey[e] * from.y);
    }
    const double dzdx = ((b.z - a.z) * (c.y - a.y) - (c.z - a.z) * (b.y - a.y)) / area;
    const double dzdy = ((c.z - a.z) * (b.x - a.x) - (b.z - a.z) * (c.x - a.x)) / area;
    const double spread = 0.5 * (std::abs(dzdx) + std::abs(dzdy));
    for (int y = int(v0); y <= int(v1); ++y)
      for (int x = int(u0); x <= int(u1); ++x) {
        const double cx = x + 0.5, cy = y + 0.5;
        bool touches = true;
        for (int e = 0; e < 3 && touches; ++e)
          touches = ex[e] * cx + ey[e] * cy + ec[e] + 0.5 * (std::abs(ex[e]) + std::abs(ey[e])) >= 0.0;
        if (!touches) continue;
        const double plane = a.z + dzdx * (cx - a.x) + dzdy * (cy - a.y);
        if (std::max(nearest, plane - spread) <= depth_[size_t(y) * width_ + x] + kDepthSlack) return true;
      }
    return false;
  }

 private:
  Basis basis_;
  double texel_ = 1.0;
  glm::dvec3 origin_{0.0};
  uint32_t width_ = 0, height_ = 0;
  std::vector<float> depth_;
};

glm::dvec3 vertex_position(const Scene& scene, const Primitive& p, uint32_t k) {
  const Vertex& v = scene.vertices.at(size_t(int64_t(scene.indices.at(p.first_index + k)) + p.vertex_offset));
  return {v.position[0], v.position[1], v.position[2]};
}

// The instance's levels of detail from the finest, or empty when they form a cycle.
std::vector<uint32_t> level_chain(const Scene& scene, uint32_t first) {
  std::vector<uint32_t> levels;
  for (int32_t p = int32_t(first); p >= 0; p = scene.primitives.at(uint32_t(p)).coarser) {
    if (levels.size() > scene.primitives.size()) return {};
    levels.push_back(uint32_t(p));
  }
  return levels;
}

// Items for every caster; visible[] set to every hour for instances that are no static caster.
std::vector<Item> bake_items(const Scene& scene, std::vector<uint16_t>& visible) {
  std::vector<Item> items;
  for (uint32_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    const Material& material = scene.materials.at(scene.material_of(instance));
    const double determinant = glm::determinant(glm::dmat3(instance.world));
    std::vector<uint32_t> levels = level_chain(scene, instance.primitive);
    if (instance.moving || material.decal || material.alpha_mode != AlphaMode::opaque || levels.empty() ||
        !std::isfinite(determinant) || determinant == 0.0) {
      visible[i] = kTodAllHours;
      continue;
    }
    Item item;
    item.instance = i;
    item.lo = glm::dvec3(INFINITY);
    item.hi = glm::dvec3(-INFINITY);
    for (uint32_t level : levels) {
      const Primitive& p = scene.primitives[level];
      for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner(instance.world * glm::dvec4(k & 1 ? p.bounds_max.x : p.bounds_min.x,
                                                            k & 2 ? p.bounds_max.y : p.bounds_min.y,
                                                            k & 4 ? p.bounds_max.z : p.bounds_min.z, 1.0));
        item.lo = glm::min(item.lo, corner);
        item.hi = glm::max(item.hi, corner);
      }
    }
    // An occluder: every level drawn at any distance, with the same occluder prefix.
    item.occluder_indices = shadow_occluder_indices(scene, i);
    item.occluder = item.occluder_indices > 0;
    std::reverse(levels.begin(), levels.end());
    item.levels = std::move(levels);
    items.push_back(std::move(item));
  }
  return items;
}

std::pair<int64_t, int64_t> sector_of(double x, double z) {
  return {int64_t(std::floor(x / kSector)), int64_t(std::floor(z / kSector))};
}

// The light's rays at baked hour `slot`: at sunrise and sunset (level light) both the setting
// light's and the rising one's, so the hours on either side, lit by one or the other, both see it.
std::vector<glm::dvec3> bake_directions(uint32_t slot) {
  const glm::dvec3 to_sun = sun_towards(slot * kTodHourStep);
  if (to_sun.y == 0.0) return {-to_sun, to_sun};
  return {to_sun.y > 0.0 ? -to_sun : to_sun};  // the sun's rays by day, the moon's (opposite) by night
}

bool caster_visible(const Scene& scene, const Item& item, const LightRaster& raster) {
  const LightTransform t = raster.transform(scene.instances[item.instance].world);
  // The box first: behind the occluders everywhere, nothing of it can show.
  {
    glm::dvec3 min(INFINITY), max(-INFINITY);
    const LightTransform world = raster.transform(glm::dmat4(1.0));
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 q = world.apply(
          glm::dvec3(k & 1 ? item.hi.x : item.lo.x, k & 2 ? item.hi.y : item.lo.y, k & 4 ? item.hi.z : item.lo.z));
      min = glm::min(min, q);
      max = glm::max(max, q);
    }
    if (!raster.rectangle_open(min.x, max.x, min.y, max.y, min.z)) return false;
  }
  for (uint32_t level : item.levels) {
    const Primitive& p = scene.primitives[level];
    for (uint32_t k = 0; k + 2 < p.index_count; k += 3)
      if (raster.triangle_visible(t.apply(vertex_position(scene, p, k)), t.apply(vertex_position(scene, p, k + 1)),
                                  t.apply(vertex_position(scene, p, k + 2))))
        return true;
  }
  return false;
}

}  // namespace

std::string tod_scene_hash(const Scene& scene) {
  std::vector<uint8_t> bytes;
  auto put = [&](const void* data, size_t size) {
    const auto* b = static_cast<const uint8_t*>(data);
    bytes.insert(bytes.end(), b, b + size);
  };
  for (const Instance& instance : scene.instances) {
    put(&instance.world[0][0], sizeof(double) * 16);
    const uint32_t fields[3] = {instance.primitive, scene.material_of(instance), instance.moving ? 1u : 0u};
    put(fields, sizeof(fields));
  }
  for (const Primitive& p : scene.primitives) {
    const uint32_t fields[4] = {p.first_index, p.index_count, uint32_t(p.vertex_offset), p.occluder_index_count};
    put(fields, sizeof(fields));
    const float distances[2] = {p.lod_distance, p.draw_distance};
    put(distances, sizeof(distances));
    put(&p.coarser, sizeof(p.coarser));
  }
  for (const Vertex& v : scene.vertices) put(v.position, sizeof(v.position));
  put(scene.indices.data(), scene.indices.size() * sizeof(uint32_t));
  return content_hash(bytes);
}

TodTable bake_tod(const Scene& scene, uint32_t seed, double size_km, const TodBakeOptions& options) {
  TodTable table;
  table.seed = seed;
  table.map_size_km = size_km;
  table.scene_hash = tod_scene_hash(scene);
  table.visible.assign(scene.instances.size(), 0);
  const std::vector<Item> items = bake_items(scene, table.visible);
  if (items.empty()) return table;

  // Casters by the sector of their box's centre; occluders in every sector their box meets.
  std::map<std::pair<int64_t, int64_t>, std::vector<uint32_t>> casters, occluders;
  double y_lo = INFINITY, y_hi = -INFINITY;
  for (uint32_t k = 0; k < items.size(); ++k) {
    const Item& item = items[k];
    const glm::dvec3 centre = 0.5 * (item.lo + item.hi);
    casters[sector_of(centre.x, centre.z)].push_back(k);
    y_lo = std::min(y_lo, item.lo.y);
    y_hi = std::max(y_hi, item.hi.y);
    if (!item.occluder) continue;
    const auto [x0, z0] = sector_of(item.lo.x, item.lo.z);
    const auto [x1, z1] = sector_of(item.hi.x, item.hi.z);
    for (int64_t x = x0; x <= x1; ++x)
      for (int64_t z = z0; z <= z1; ++z) occluders[{x, z}].push_back(k);
  }
  std::vector<std::pair<int64_t, int64_t>> sectors;
  for (const auto& [sector, list] : casters) sectors.push_back(sector);

  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t s = next++; s < sectors.size(); s = next++) {
      const auto [sx, sz] = sectors[s];
      std::vector<uint32_t> window;
      for (int64_t x = sx - 1; x <= sx + 1; ++x)
        for (int64_t z = sz - 1; z <= sz + 1; ++z)
          if (auto it = occluders.find({x, z}); it != occluders.end())
            window.insert(window.end(), it->second.begin(), it->second.end());
      std::sort(window.begin(), window.end());
      window.erase(std::unique(window.begin(), window.end()), window.end());
      const glm::dvec3 lo((sx - 1) * kSector, y_lo, (sz - 1) * kSector),
          hi((sx + 2) * kSector, y_hi, (sz + 2) * kSector);
      for (uint32_t slot = 0; slot < kTodHours; ++slot)
        for (const glm::dvec3& travel : bake_directions(slot)) {
          LightRaster raster(light_basis(travel), lo, hi, options.texel_metres);
          for (uint32_t k : window) {
            const Item& item = items[k];
            const Primitive& p = scene.primitives[item.levels.back()];
            const LightTransform t = raster.transform(scene.instances[item.instance].world);
            for (uint32_t v = 0; v + 2 < item.occluder_indices; v += 3)
              raster.occlude(t.apply(vertex_position(scene, p, v)), t.apply(vertex_position(scene, p, v + 1)),
                             t.apply(vertex_position(scene, p, v + 2)));
          }
          raster.settle();
          for (uint32_t k : casters.at(sectors[s])) {
            uint16_t& bits = table.visible[items[k].instance];
            if (!(bits >> slot & 1) && caster_visible(scene, items[k], raster)) bits = uint16_t(bits | 1u << slot);
          }
        }
    }
  };
  const uint32_t threads =
      std::max(1u, std::min<uint32_t>(options.threads ? options.threads : std::thread::hardware_concurrency(),
                                      uint32_t(sectors.size())));
  std::vector<std::thread> pool;
  for (uint32_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  return table;
}

namespace {

// The file: this header, a 16-bit mask per instance, and the content hash of everything before
// it (32 hex digits). Little-endian, as every machine nightcap builds on.
struct TodFileHeader {
  char magic[8];
  uint32_t version;
  uint32_t seed;
  double map_size_km;
  double latitude_degrees;
  uint32_t hours;
  uint32_t instances;
  char scene_hash[32];
};
static_assert(sizeof(TodFileHeader) == 72);
constexpr char kTodMagic[8] = {'N', 'C', 'T', 'O', 'D', '\r', '\n', '\x1a'};
constexpr uint32_t kTodVersion = 1;
constexpr size_t kTodHashBytes = 32;

}  // namespace

void write_tod(const TodTable& table, const std::filesystem::path& path) {
  TodFileHeader header{};
  std::memcpy(header.magic, kTodMagic, sizeof(kTodMagic));
  header.version = kTodVersion;
  header.seed = table.seed;
  header.map_size_km = table.map_size_km;
  header.latitude_degrees = kTodLatitudeDegrees;
  header.hours = kTodHours;
  header.instances = uint32_t(table.visible.size());
  if (table.scene_hash.size() != sizeof(header.scene_hash)) throw SceneError("time-of-day table without a scene hash");
  std::memcpy(header.scene_hash, table.scene_hash.data(), sizeof(header.scene_hash));
  std::vector<uint8_t> bytes(sizeof(header) + table.visible.size() * sizeof(uint16_t));
  std::memcpy(bytes.data(), &header, sizeof(header));
  if (!table.visible.empty())
    std::memcpy(bytes.data() + sizeof(header), table.visible.data(), table.visible.size() * sizeof(uint16_t));
  const std::string checksum = content_hash(bytes);
  bytes.insert(bytes.end(), checksum.begin(), checksum.end());

  std::filesystem::path temporary = path;
  temporary += ".tmp-" + std::to_string(getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw SceneError(path.string() + ": cannot write the time-of-day table");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw SceneError(path.string() + ": cannot write the time-of-day table (" + error.message() + ")");
  }
}

TodTable read_tod(const std::filesystem::path& path, uint32_t seed, double size_km, const Scene& scene) {
  const std::string name = path.string() + ": ";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(name + "cannot read the time-of-day table");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  TodFileHeader header{};
  if (bytes.size() < sizeof(kTodMagic) || std::memcmp(bytes.data(), kTodMagic, sizeof(kTodMagic)) != 0)
    throw SceneError(name + "not a time-of-day table (`nightcap bake-tod` writes them)");
  if (bytes.size() < sizeof(header) + kTodHashBytes)
    throw SceneError(name + "truncated (" + std::to_string(bytes.size()) + " bytes, less than a header)");
  std::memcpy(&header, bytes.data(), sizeof(header));
  if (header.version != kTodVersion)
    throw SceneError(name + "time-of-day table version " + std::to_string(header.version) + ", this nightcap reads " +
                     std::to_string(kTodVersion));
  const size_t expected = sizeof(header) + size_t(header.instances) * sizeof(uint16_t) + kTodHashBytes;
  if (bytes.size() != expected)
    throw SceneError(name + (bytes.size() < expected ? "truncated" : "has trailing bytes") + " (" +
                     std::to_string(bytes.size()) + " bytes; its header announces " + std::to_string(expected) + ")");
  const std::string stored(bytes.end() - kTodHashBytes, bytes.end());
  if (content_hash(std::span(bytes.data(), bytes.size() - kTodHashBytes)) != stored)
    throw SceneError(name + "corrupt (its checksum does not match its contents)");
  if (header.hours != kTodHours || header.latitude_degrees != kTodLatitudeDegrees)
    throw SceneError(name + "baked for " + std::to_string(header.hours) + " hours at latitude " +
                     std::to_string(header.latitude_degrees) + "°; this nightcap uses " + std::to_string(kTodHours) +
                     " at " + std::to_string(kTodLatitudeDegrees) + "°");
  char wanted_size[32], baked_size[32];
  std::snprintf(wanted_size, sizeof(wanted_size), "%g", size_km);
  std::snprintf(baked_size, sizeof(baked_size), "%g", header.map_size_km);
  if (header.seed != seed || header.map_size_km != size_km)
    throw SceneError(name + "baked for the map of seed " + std::to_string(header.seed) + ", " + baked_size +
                     " km; this render is of seed " + std::to_string(seed) + ", " + wanted_size +
                     " km (bake it with --scene-seed " + std::to_string(seed) + " --map-size " + wanted_size + ")");
  TodTable table;
  table.seed = header.seed;
  table.map_size_km = header.map_size_km;
  table.scene_hash.assign(header.scene_hash, sizeof(header.scene_hash));
  if (header.instances != scene.instances.size() || table.scene_hash != tod_scene_hash(scene))
    throw SceneError(name + "baked for another build of this map (its instances differ): bake it again");
  table.visible.resize(header.instances);
  if (header.instances)
    std::memcpy(table.visible.data(), bytes.data() + sizeof(header), table.visible.size() * sizeof(uint16_t));
  for (uint16_t bits : table.visible)
    if (bits & ~kTodAllHours) throw SceneError(name + "corrupt (a mask names hours beyond the 12 baked)");
  return table;
}

}  // namespace nightcap
