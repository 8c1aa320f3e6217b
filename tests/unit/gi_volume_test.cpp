// The GI volume (gi.plan, gi.volume, gi/volume_lookup.glsl) against references in double:
// - a cell: every cell of the map's street volume on its first frame against a CPU gather of the
//   same records (probes.slots, probes.irradiance, sky.irradiance, shadow.topdown) in double,
//   within 10⁻³ of the cell's largest coefficient plus a half's rounding of each; cells whose
//   answer turns on a comparison within float rounding (the sky's visibility at a depth step, two
//   probes at the same distance) are left out and counted (under 1%);
// - interpolation: gi_volume_irradiance() on the GPU against the trilinear formula and the
//   bands' sum in double over the same halves (gi_reference.h), cells that gathered nothing left
//   out, within 10⁻⁵ relative, for L2 and L1, with the weight that mixes it with the sky's
//   across the outer half cell and outside;
// - refresh: a still camera gathers the whole volume on frame 0 and nothing after (frame 3's
//   volume is frame 0's, bit for bit); a driving camera gathers exactly the cells that scrolled in
//   (as disjoint slabs) and the boxes of the probes captured that frame, and keeps every other
//   cell bit for bit at its toroidal texel; a cut gathers the whole volume again.
#include <cmath>
#include <cstring>
#include <random>
#include <set>
#include <tuple>

#include "passes/assembly/renderer.h"
#include "passes/core/history_name.h"
#include "passes/core/shader.h"
#include "passes/gi/volume_layout.h"
#include "passes/probes/capture_layout.h"
#include "passes/shadow/topdown_layout.h"
#include "passes/sky/ibl.glsl.h"
#include "tests/reference/gi_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using glm::dvec3;
using glm::ivec3;

using Coefficients = std::array<dvec3, 9>;

// What a cell's gather reads, decoded from a frame.
struct GatherInputs {
  GpuGiVolume volume{};
  GpuTopdown topdown{};
  std::vector<uint8_t> topdown_map;
  uint32_t topdown_side = 0;
  std::vector<GpuProbeSlot> slots;
  std::vector<GpuSkyIrradiance> probe_irradiance;
  GpuSkyIrradiance sky{};
  double fade_metres = 4.0;
};

using reference::gi_stored_cell;
using reference::gi_toroidal;

// A CPU gather of one cell in double (volume.comp's definition): its coefficients and whether a
// probe lights it; nullopt where the answer turns on a comparison within float rounding.
struct Gathered {
  Coefficients c;
  bool from_probes = false;
};
std::optional<Gathered> cpu_gather(const GatherInputs& in, const ivec3& cell) {
  const dvec3 origin(glm::vec3(in.volume.origin));
  const double side = in.volume.origin.w;
  const dvec3 centre = origin + (dvec3(cell - ivec3(in.volume.origin_cell)) + 0.5) * side;
  // topdown.glsl's sky visibility straight up.
  const glm::dmat4 map_from_world(in.topdown.map_from_world);
  const glm::dvec4 clip = map_from_world * glm::dvec4(centre + dvec3(0, 1, 0) * double(in.topdown.extent.w), 1.0);
  double open = 1.0;
  if (std::abs(clip.x) <= 1.0 && std::abs(clip.y) <= 1.0) {
    const int n = int(in.topdown.extent.z);
    const glm::dvec2 at = (glm::dvec2(clip) * 0.5 + 0.5) * double(in.topdown.extent.z) - 0.5;
    const glm::ivec2 base(glm::floor(at));
    const glm::dvec2 f = at - glm::dvec2(base);
    const double lowest_above = clip.z - 0.05 / double(in.topdown.extent.y);
    double answers[4];
    for (int k = 0; k < 4; ++k) {
      const glm::ivec2 texel = glm::clamp(base + glm::ivec2(k & 1, k >> 1), glm::ivec2(0), glm::ivec2(n - 1));
      uint16_t code;
      std::memcpy(&code, in.topdown_map.data() + (size_t(texel.y) * in.topdown_side + size_t(texel.x)) * 2, 2);
      const double depth = code / 65535.0;
      if (std::abs(depth - lowest_above) < 1e-5) return std::nullopt;
      answers[k] = depth >= lowest_above ? 1.0 : 0.0;
    }
    open = glm::mix(glm::mix(answers[0], answers[1], f.x), glm::mix(answers[2], answers[3], f.x), f.y);
  }
  Coefficients c;
  for (int i = 0; i < 9; ++i) c[i] = dvec3(glm::vec3(in.sky.coefficients[i])) * open;
  // The two nearest probes whose boxes hold the centre (reflection.glsl).
  struct Near {
    double distance, weight;
    size_t index;
  };
  std::vector<Near> near;
  for (size_t k = 0; k < in.slots.size(); ++k) {
    const GpuProbeSlot& s = in.slots[k];
    const dvec3 inside = glm::min(centre - dvec3(glm::vec3(s.box_min)), dvec3(glm::vec3(s.box_max)) - centre);
    const double margin = std::min({inside.x, inside.y, inside.z});
    if (margin <= 0.0) continue;
    near.push_back({glm::length(centre - dvec3(glm::vec3(s.position))),
                    std::clamp(margin / std::max(in.fade_metres, 1e-6), 0.0, 1.0), k});
  }
  std::sort(near.begin(), near.end(), [](const Near& a, const Near& b) { return a.distance < b.distance; });
  for (size_t k = 1; k < near.size() && k < 3; ++k)
    if (near[k].distance - near[k - 1].distance < 1e-3) return std::nullopt;
  if (near.size() > 2) near.resize(2);
  if (!near.empty()) {
    Coefficients sum{};
    double total = 0.0;
    for (const Near& p : near) {
      const uint32_t slot = uint32_t(in.slots[p.index].position.w);
      for (int i = 0; i < 9; ++i) sum[i] += p.weight * dvec3(glm::vec3(in.probe_irradiance.at(slot).coefficients[i]));
      total += p.weight;
    }
    for (int i = 0; i < 9; ++i) c[i] = total > 1.0 ? sum[i] / total : sum[i] + (1.0 - total) * c[i];
  }
  return Gathered{c, !near.empty()};
}

// One ULP of a half at x, halved: what rounding to the nearest moves x by at most.
double half_rounding(double x) { return std::ldexp(1.0, std::max(std::ilogb(std::max(std::abs(x), 1e-30)), -14) - 11); }

const char* kLookupShader = R"(#version 460
#include "sky/sh.glsl"
#include "gi/volume_layout.glsl.h"
layout(local_size_x = 64) in;
layout(std140, set = 0, binding = 0) uniform GiVolumeBlock { GpuGiVolume gi; };
layout(set = 0, binding = 1) uniform sampler3D gi_cells;
layout(set = 0, binding = 2) readonly buffer Cases { vec4 cases[]; };
layout(set = 0, binding = 3) buffer Results { vec4 results[]; };
#include "gi/volume_lookup.glsl"
void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= cases.length() / 2) return;
  vec3 irradiance_n;
  float inside = gi_volume_irradiance(cases[2 * i].xyz, cases[2 * i + 1].xyz, irradiance_n);
  results[i] = vec4(irradiance_n, inside);
}
)";

class GiVolume : public GpuTest {
 protected:
  static RenderSettings small(CameraPath::Motion motion) {
    RenderSettings settings;
    settings.width = 160;
    settings.height = 90;
    settings.path.motion = motion;
    return settings;
  }

  static GiPlan plan_of(const RenderedFrame& frame) {
    return host_records<GiPlan>(*frame.execution.final_version("gi.plan")->bytes).at(0);
  }
  static std::vector<GiBox> boxes_of(const RenderedFrame& frame) {
    return host_records<GiBox>(*frame.execution.final_version("gi.refresh")->bytes);
  }

  // gi_volume_irradiance() on the GPU: (irradiance about n over π, the volume's weight) per case.
  std::vector<glm::vec4> lookup(const GpuGiVolume& volume, const std::vector<uint8_t>& cells_bytes,
                                const std::vector<std::pair<dvec3, dvec3>>& cases) {
    std::vector<float> packed;
    for (const auto& [p, n] : cases)
      for (const glm::dvec4& v : {glm::dvec4(p, 0.0), glm::dvec4(n, 0.0)})
        for (int k = 0; k < 4; ++k) packed.push_back(float(v[k]));
    const uint64_t bytes = cases.size() * 16;
    const uint32_t cells = uint32_t(volume.origin_cell.w);
    PassDecl pass = PassDecl("gi.lookup_test", PassType::compute)
                        .read("gi.volume_data", Use::uniform_buffer)
                        .read("gi.volume", Use::sampled)
                        .read("gi.cases", Use::storage_read)
                        .write("gi.results", Use::storage_write, BufferDecl{kinds::buffer, bytes})
                        .shader("test/gi_lookup.comp")
                        .run([&](PassContext& ctx) {
                          ctx.bind_pipeline();
                          ctx.push_declared();
                          vkCmdDispatch(ctx.cmd(), uint32_t(cases.size() + 63) / 64, 1, 1);
                        });
    const IsolatedInput data = record_input(volume);
    IsolatedInput image = GpuTest::image(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::colour, cells, cells, cells_bytes);
    image.desc.extent.depth = cells * kGiVolumeTexels;
    const IsolatedRun run = run_isolated(
        *gpu_, *cache_, pass,
        {{"gi.volume_data", data}, {"gi.volume", image}, {"gi.cases", records_input(std::span<const float>(packed))}},
        {}, 1, 1, [](const std::string&, const std::string& path, const std::string& bindings) {
          return compile_glsl(path, kLookupShader, bindings);
        });
    std::vector<glm::vec4> out(cases.size());
    std::memcpy(out.data(), run.outputs.at("gi.results")->data(), bytes);
    return out;
  }
};

TEST_F(GiVolume, EveryCellMatchesACpuGatherInDouble) {
  const Scene scene = build_map({1, 16.0, Shot::street});
  Renderer renderer(*gpu_, scene, small(CameraPath::Motion::still));
  const RenderedFrame frame = renderer.render_frame(0, true);
  ASSERT_TRUE(first_non_finite(frame.execution).empty()) << first_non_finite(frame.execution);
  const GiPlan plan = plan_of(frame);
  ASSERT_EQ(plan.refresh, uint32_t(GiRefresh::no_history));
  ASSERT_EQ(plan.refreshed_cells, plan.cells * plan.cells * plan.cells);

  GatherInputs in;
  in.volume = host_records<GpuGiVolume>(*frame.execution.final_version("gi.volume_data")->bytes).at(0);
  in.topdown = host_records<GpuTopdown>(*frame.execution.final_version("shadow.topdown_data")->bytes).at(0);
  const VersionData& map = *frame.execution.final_version("shadow.topdown");
  in.topdown_map = *map.bytes;
  in.topdown_side = map.desc.extent.width;
  in.slots = host_records<GpuProbeSlot>(*frame.execution.final_version("probes.slots")->bytes);
  in.probe_irradiance = host_records<GpuSkyIrradiance>(*frame.execution.final_version("probes.irradiance")->bytes);
  in.sky = host_records<GpuSkyIrradiance>(*frame.execution.final_version("sky.irradiance")->bytes).at(0);
  ASSERT_GT(in.slots.size(), 1u) << "the street's probes are captured";
  const std::vector<uint8_t>& volume = *frame.execution.final_version("gi.volume")->bytes;

  const int cells = int(plan.cells);
  const ivec3 origin = ivec3(in.volume.origin_cell);
  size_t compared = 0, left_out = 0, in_probe_boxes = 0, wrong = 0;
  double worst = 0.0;
  for (int z = 0; z < cells; ++z)
    for (int y = 0; y < cells; ++y)
      for (int x = 0; x < cells; ++x) {
        const ivec3 cell = origin + ivec3(x, y, z);
        const std::optional<Gathered> gathered = cpu_gather(in, cell);
        if (!gathered) {
          ++left_out;
          continue;
        }
        const Coefficients* expected = &gathered->c;
        if (gathered->from_probes) ++in_probe_boxes;
        const std::array<double, 28> got = gi_stored_cell(volume, plan.cells, gi_toroidal(cell, cells));
        double largest = 0.0;
        for (const dvec3& c : *expected) largest = std::max({largest, std::abs(c.x), std::abs(c.y), std::abs(c.z)});
        for (int j = 0; j < 27; ++j) {
          const double e = (*expected)[j / 3][j % 3];
          const double error = std::abs(got[j] - e);
          worst = std::max(worst, error / std::max(largest, 1e-30));
          if (error - half_rounding(e) > 1e-3 * largest) ++wrong;
        }
        ++compared;
      }
  std::printf(
      "gi.volume: %zu cells against the CPU gather, %zu left out, worst %.3g of the cell's largest (a half's rounding "
      "included)\n",
      compared, left_out, worst);
  EXPECT_EQ(wrong, 0u);
  EXPECT_LT(double(left_out), 0.01 * double(compared + left_out));
  EXPECT_GT(in_probe_boxes, 0u);
}

TEST_F(GiVolume, InterpolationIsTheTrilinearFormula) {
  const uint32_t cells = 8;
  std::mt19937 rng(11);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * double(rng() >> 8) / 16777216.0; };
  // Band 0 well above the others: the irradiance stays positive, so relative errors mean something.
  std::vector<uint8_t> bytes(size_t(cells) * cells * cells * kGiVolumeTexels * 8);
  for (size_t texel = 0; texel < bytes.size() / 8; ++texel)
    for (int m = 0; m < 4; ++m) {
      const size_t block = texel / (size_t(cells) * cells * cells);
      const int j = int(4 * block) + m;
      // One cell in seven gathered nothing (zeros): left out of the interpolation.
      const bool gathered_nothing = (texel % (size_t(cells) * cells * cells)) % 7 == 3;
      const double value = gathered_nothing ? 0.0 : (j < 3 ? uniform(1.0, 2.0) : uniform(-0.15, 0.15));
      const uint16_t h = float_to_half(float(value));
      std::memcpy(bytes.data() + texel * 8 + size_t(m) * 2, &h, 2);
    }
  for (const uint32_t bands : {2u, 1u}) {
    GpuGiVolume volume{};
    volume.origin = glm::vec4(-8.3f, -7.9f, -8.1f, 2.0f);
    volume.origin_cell = glm::ivec4(13, -7, 2, int32_t(cells));  // the seams of the toroidal texels inside
    volume.evaluation = glm::uvec4(bands, bands == 1 ? 3u : kGiVolumeTexels, 0u, 0u);
    std::vector<std::pair<dvec3, dvec3>> cases;
    for (int i = 0; i < 512; ++i) {
      // In cell-centre coordinates: most within the outer cells' centres [0, cells − 1], some
      // across the outer half cell, a few outside.
      const double m = i < 384 ? 0.0 : (i < 480 ? 0.45 : 1.5);
      const dvec3 f(uniform(-m, cells - 1 + m), uniform(-m, cells - 1 + m), uniform(-m, cells - 1 + m));
      const dvec3 p = dvec3(glm::vec3(volume.origin)) + (f + 0.5) * 2.0;
      const dvec3 n = glm::normalize(dvec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)) + 1e-3);
      cases.push_back({dvec3(glm::vec3(p)), dvec3(glm::vec3(n))});
    }
    const std::vector<glm::vec4> got = lookup(volume, bytes, cases);
    double worst = 0.0;
    size_t inside = 0, mixed = 0, outside = 0;
    for (size_t i = 0; i < cases.size(); ++i) {
      const auto& [p, n] = cases[i];
      const dvec3 f = (p - dvec3(glm::vec3(volume.origin))) / 2.0 - 0.5;
      const dvec3 beyond = glm::max(-f, f - double(cells - 1));
      const double margin = std::max({beyond.x, beyond.y, beyond.z});
      if (margin >= 0.5) {
        ++outside;
        EXPECT_EQ(got[i].w, 0.0f) << i;
        continue;
      }
      const reference::GiLookup expected = reference::gi_lookup(volume, bytes, p, n, bands);
      if (expected.weight == 0.0) {  // all eight cells gathered nothing
        EXPECT_EQ(got[i].w, 0.0f) << i;
        continue;
      }
      (margin > 0.0 ? mixed : inside) += 1;
      EXPECT_NEAR(got[i].w, expected.weight, 1e-6) << i;
      const dvec3 e = expected.irradiance_n;
      for (int c = 0; c < 3; ++c) {
        ASSERT_GT(e[c], 0.0);
        worst = std::max(worst, std::abs(got[i][c] - e[c]) / e[c]);
      }
    }
    std::printf(
        "gi_volume_irradiance, L%u: %zu inside, %zu across the outer half cell, %zu outside: worst %.3g "
        "relative to the trilinear formula in double\n",
        bands, inside, mixed, outside, worst);
    EXPECT_LE(worst, 1e-5);
    EXPECT_GT(inside, 0u);
    EXPECT_GT(mixed, 0u);
    EXPECT_GT(outside, 0u);
  }
}

TEST_F(GiVolume, AStillCameraGathersOnlyOnItsFirstFrame) {
  const Scene scene = build_map({1, 16.0, Shot::street});
  Renderer renderer(*gpu_, scene, small(CameraPath::Motion::still));
  std::vector<uint8_t> first;
  for (uint32_t f = 0; f < 4; ++f) {
    const RenderedFrame frame = renderer.render_frame(f, true);
    const GiPlan plan = plan_of(frame);
    const std::vector<uint8_t>& volume = *frame.execution.final_version("gi.volume")->bytes;
    if (f == 0) {
      EXPECT_EQ(plan.refresh, uint32_t(GiRefresh::no_history));
      EXPECT_EQ(plan.refreshed_cells, plan.cells * plan.cells * plan.cells);
      first = volume;
      continue;
    }
    EXPECT_EQ(plan.refresh, uint32_t(GiRefresh::kept)) << "frame " << f;
    EXPECT_EQ(plan.refreshed_cells, 0u) << "frame " << f;
    EXPECT_EQ(boxes_of(frame).size(), 0u) << "frame " << f;
    EXPECT_TRUE(volume == first) << "frame " << f << " changed the volume";
  }
}

TEST_F(GiVolume, ADrivingCameraGathersWhatScrolledInAndKeepsTheRest) {
  const Scene scene = build_map({1, 16.0, Shot::street});
  RenderSettings settings = small(CameraPath::Motion::drive);
  // Quarter-metre cells: the car (14 m/s, 23 cm a frame) crosses about one a frame.
  settings.params["gi"]["cells"] = 16;
  settings.params["gi.plan"]["cell_metres"] = 0.25;
  settings.path.cuts = {5};
  Renderer renderer(*gpu_, scene, settings);
  std::vector<uint8_t> before_volume;
  GiPlan before{};
  uint32_t scrolled_frames = 0;
  for (uint32_t f = 0; f < 6; ++f) {
    const RenderedFrame frame = renderer.render_frame(f, true);
    const GiPlan plan = plan_of(frame);
    const std::vector<GiBox> boxes = boxes_of(frame);
    const std::vector<uint8_t>& volume = *frame.execution.final_version("gi.volume")->bytes;
    const int cells = int(plan.cells);
    const ivec3 origin(plan.origin_cell[0], plan.origin_cell[1], plan.origin_cell[2]);
    if (f == 0 || f == 5) {
      EXPECT_EQ(plan.refresh, uint32_t(GiRefresh::no_history)) << "frame " << f;
      ASSERT_EQ(boxes.size(), 1u);
      EXPECT_EQ(boxes[0].cells, uint32_t(cells * cells * cells));
    } else {
      EXPECT_EQ(plan.refresh, uint32_t(GiRefresh::kept)) << "frame " << f;
      const ivec3 was(before.origin_cell[0], before.origin_cell[1], before.origin_cell[2]);
      std::set<std::tuple<int, int, int>> scrolled, gathered;
      for (const GiBox& box : boxes)
        for (uint32_t z = 0; z < box.size[2]; ++z)
          for (uint32_t y = 0; y < box.size[1]; ++y)
            for (uint32_t x = 0; x < box.size[0]; ++x) {
              const auto cell = std::make_tuple(box.min[0] + int(x), box.min[1] + int(y), box.min[2] + int(z));
              gathered.insert(cell);
              if (box.reason == uint32_t(GiBoxReason::scrolled_in)) {
                EXPECT_TRUE(scrolled.insert(cell).second) << "frame " << f << ": slabs overlap";
              }
            }
      size_t expected_scrolled = 0;
      for (int z = 0; z < cells; ++z)
        for (int y = 0; y < cells; ++y)
          for (int x = 0; x < cells; ++x) {
            const ivec3 cell = origin + ivec3(x, y, z);
            const bool was_inside =
                glm::all(glm::greaterThanEqual(cell, was)) && glm::all(glm::lessThan(cell, was + cells));
            const auto key = std::make_tuple(cell.x, cell.y, cell.z);
            EXPECT_EQ(scrolled.count(key) != 0, !was_inside) << "frame " << f;
            expected_scrolled += was_inside ? 0 : 1;
            if (gathered.count(key)) continue;
            const ivec3 texel = gi_toroidal(cell, cells);
            EXPECT_TRUE(gi_stored_cell(volume, plan.cells, texel) == gi_stored_cell(before_volume, plan.cells, texel))
                << "frame " << f << ": a kept cell changed";
          }
      if (expected_scrolled > 0) ++scrolled_frames;
    }
    before = plan;
    before_volume = volume;
  }
  EXPECT_GE(scrolled_frames, 2u) << "the camera crossed cells";
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
