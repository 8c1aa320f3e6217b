// Geometry and screen passes against their references: normals.pack, depth, vertex streams, motion.stencil, decals.
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/core/format.h"
#include "passes/core/isolated.h"
#include "passes/core/resource_kind.h"
#include "passes/depth/kinds.h"
#include "passes/depth/stage.h"
#include "passes/frame/gpu_types.h"
#include "passes/frame/vertex_streams.h"
#include "passes/gbuffer/kinds.h"
#include "passes/motion/stage.h"
#include "passes/normals/bfn_lut.h"
#include "passes/normals/stage.h"
#include "passes/scene/scene.h"
#include "passes/scene/scene_kit.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/decal_reference.h"
#include "tests/reference/depth_half_reference.h"
#include "tests/reference/motion_mask_reference.h"

namespace nc = nightcap;
namespace ref = nightcap::reference;

namespace nightcap::bench {

namespace {

// A stencil tag per pixel: every class and flag of passes/scene/scene.h, one pixel in 200 moving,
// hair or foliage (the rest plain, road, body, face or vehicle).
std::vector<uint8_t> bench_tags(size_t pixels, std::mt19937& rng) {
  namespace st = nc::stencil;
  const uint8_t untagged[] = {st::plain, st::road, st::body, st::face, st::vehicle};
  const uint8_t tagged[] = {st::hair, st::foliage, st::body | st::moving, st::vehicle | st::moving};
  std::vector<uint8_t> tags(pixels);
  for (uint8_t& t : tags)
    t = rng() % 200 == 0 ? tagged[rng() % std::size(tagged)] : untagged[rng() % std::size(untagged)];
  return tags;
}

}  // namespace

// normals.pack: LUT size against mean/max angular error over a Fibonacci sphere.
void bench_normals(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t count) {
  const uint32_t width = 2048, height = (count + width - 1) / width;
  std::vector<uint8_t> normals(size_t(width) * height * 4), material(size_t(width) * height * 4, 128);
  std::vector<glm::dvec3> inputs(size_t(width) * height);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (size_t i = 0; i < inputs.size(); ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / inputs.size(), r = std::sqrt(1.0 - y * y);
    const glm::dvec3 d(std::cos(golden * i) * r, y, std::sin(golden * i) * r);
    auto code = [](double v) { return uint32_t(std::lround((v * 0.5 + 0.5) * 1023.0)); };
    const uint32_t w = code(d.x) | code(d.y) << 10 | code(d.z) << 20;
    std::memcpy(normals.data() + 4 * i, &w, 4);
    inputs[i] = glm::normalize(glm::dvec3((w & 1023) / 1023.0 * 2 - 1, ((w >> 10) & 1023) / 1023.0 * 2 - 1,
                                          ((w >> 20) & 1023) / 1023.0 * 2 - 1));
  }
  table() << "\n## normals.pack: LUT size vs error (" << inputs.size() << " directions, " << width << "x" << height
          << ")\n"
          << std::left << std::setw(12) << "lut" << std::right << std::setw(12) << "build ms" << std::setw(12)
          << "gpu ms" << std::setw(14) << "mean deg" << std::setw(12) << "max deg"
          << "\n";
  for (uint32_t lut_size : {64u, 256u, 1024u, 2048u}) {
    const double start = now_ms();
    std::vector<uint8_t> lut = nc::build_bfn_lut(lut_size);
    const double build = now_ms() - start;
    std::vector<double> times;
    nc::IsolatedRun run;
    for (int r = 0; r < 3; ++r) {
      run = nc::run_isolated(
          gpu, cache, nc::normals_pack_pass(),
          {{"gbuffer.normal", image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, nc::kinds::normal, width, height, normals)},
           {"gbuffer.material", image(VK_FORMAT_R8G8B8A8_UNORM, nc::kinds::material, width, height, material)},
           {"normals.bfn_lut", image(VK_FORMAT_R8_UINT, nc::kinds::lookup_table, lut_size, lut_size, lut)}},
          {}, width, height, nc::builtin_shaders());
      times.push_back(gpu_ms(run));
    }
    const auto& packed = *run.outputs.at("normals.packed");
    double sum = 0, worst = 0;
    for (size_t i = 0; i < inputs.size(); ++i) {
      const uint8_t* c = packed.data() + 4 * i;
      const glm::dvec3 s =
          glm::normalize(glm::dvec3(nc::decode_signed8(c[0]), nc::decode_signed8(c[1]), nc::decode_signed8(c[2])));
      const double e = glm::degrees(std::atan2(glm::length(glm::cross(s, inputs[i])), glm::dot(s, inputs[i])));
      sum += e;
      worst = std::max(worst, e);
    }
    table() << std::left << std::setw(12) << lut_size << std::right << std::fixed << std::setprecision(1)
            << std::setw(12) << build << std::setprecision(3) << std::setw(12) << median(times) << std::setprecision(4)
            << std::setw(14) << sum / inputs.size() << std::setw(12) << worst << "\n";
    const std::string row = "normals_pack.lut_" + std::to_string(lut_size);
    figure(row + ".build_ms", build);
    figure(row + ".gpu_ms", median(times));
    figure(row + ".mean_deg", sum / inputs.size());
    figure(row + ".max_deg", worst);
  }
}

// depth.convert and depth.pyramid: time, and error against double-precision / exact references;
// depth.convert's time covers its three outputs (depth.linear, depth.half, stencil.half), which
// one dispatch writes.
void bench_depth(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  std::mt19937 rng(7);
  std::vector<float> device_depth(size_t(width) * height);
  for (float& d : device_depth) d = float(rng() % 1000000 + 1) * 1e-6f;
  const std::vector<uint8_t> tags = bench_tags(device_depth.size(), rng);
  std::vector<uint8_t> depth_bytes(device_depth.size() * 5, 0);
  std::memcpy(depth_bytes.data(), device_depth.data(), device_depth.size() * 4);
  std::memcpy(depth_bytes.data() + device_depth.size() * 4, tags.data(), tags.size());
  nc::GpuView camera{};
  camera.projection_params.x = 0.05f;
  const nc::IsolatedInput camera_in = nc::record_input(camera);
  std::vector<double> times, wall;
  nc::IsolatedRun convert;
  for (int r = 0; r < 4; ++r) {  // the first run compiles the pipeline
    const double start = now_ms();
    convert = nc::run_isolated(
        gpu, cache, nc::depth_convert_pass(),
        {{"frame.views", camera_in},
         {"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, nc::kinds::depth_stencil, width, height, depth_bytes)}},
        nc::depth_convert_pass().default_params(), width, height, nc::builtin_shaders());
    if (r > 0) wall.push_back(now_ms() - start);
    if (r > 0) times.push_back(gpu_ms(convert));
  }
  const auto& linear = *convert.outputs.at("depth.linear");
  double worst = 0;
  for (size_t i = 0; i < device_depth.size(); ++i) {
    float v;
    std::memcpy(&v, linear.data() + 4 * i, 4);
    const double exact = double(0.05f) / double(device_depth[i]);
    worst = std::max(worst, std::abs(v - exact) / exact);
  }
  // The half outputs against tests/reference/depth_half_reference.h: depth error in half ULPs of
  // the exact value (the unit test bounds it by 0.5 plus a float ULP), stencil texels that differ.
  const ref::HalfDepthStencil half = ref::half_depth_stencil(device_depth, tags, width, height, double(0.05f),
                                                             nc::depth_convert_pass().default_params().at("sky_depth"));
  const auto& half_depth = *convert.outputs.at("depth.half");
  const auto& half_stencil = *convert.outputs.at("stencil.half");
  double worst_half_ulps = 0;
  size_t stencil_wrong = 0;
  for (size_t i = 0; i < half.metres.size(); ++i) {
    uint16_t bits;
    std::memcpy(&bits, half_depth.data() + 2 * i, 2);
    const double exact = half.metres[i];
    const double ulp = std::ldexp(1.0, std::max(std::ilogb(exact), -14) - 10);
    worst_half_ulps = std::max(worst_half_ulps, std::abs(nc::half_to_float(bits) - exact) / ulp);
    stencil_wrong += half_stencil[i] != half.stencil[i];
  }
  // lavapipe's timestamps around this one compute dispatch come out far below its work (hundredths
  // of a millisecond, against about 16 in the city frame), so the isolated run's wall clock is
  // printed too: an upper bound, with the upload of the inputs and the readback of the outputs.
  table() << "\n## depth (" << width << "x" << height << ")\n"
          << "depth.convert   gpu " << std::fixed << std::setprecision(3) << median(times) << " ms (timestamps), "
          << median(wall) << " ms isolated wall clock, max rel error vs double " << std::scientific
          << std::setprecision(2) << worst << "; depth.half max " << std::fixed << std::setprecision(4)
          << worst_half_ulps << " half ULP, stencil.half " << stencil_wrong << " texels differ\n";
  figure("depth_convert.gpu_ms", median(times));
  figure("depth_convert.isolated_wall_ms", median(wall));
  figure("depth_convert.max_rel_err", worst);
  figure("depth_convert.half_max_half_ulps", worst_half_ulps);
  figure("depth_convert.stencil_half_mismatches", double(stencil_wrong));
  times.clear();
  nc::IsolatedRun pyramid;
  for (int r = 0; r < 3; ++r) {
    pyramid = nc::run_isolated(
        gpu, cache, nc::depth_pyramid_pass(),
        {{"depth.linear", {convert.output_descs.at("depth.linear"), convert.outputs.at("depth.linear")}}}, {}, width,
        height, nc::builtin_shaders());
    times.push_back(gpu_ms(pyramid));
  }
  table() << "depth.pyramid   gpu " << std::fixed << std::setprecision(3) << median(times)
          << " ms, exact by construction (tests/unit/depth_pyramid_test.cpp)\n";
  figure("depth_pyramid.gpu_ms", median(times));
}

// scene.geometry's positions against the bits they keep: a scene's vertices quantised on the CPU
// in their primitives' boxes with 8, 10, 12 and 16 bits per axis (16 ships), the distance to the
// float position in object-space millimetres (max, mean over vertices), the time to quantise
// them, and the bytes a vertex would take (positions in 4 bytes up to 10 bits, else 8; the other
// streams' 20 bytes as shipped). Then the shipped buffer against the 72-byte float layout. The
// built-in city is boxes whose corners are their bounds, exact at any bit count; DamagedHelmet
// shows a curve.
void bench_vertex_streams(const std::string& key, const std::string& label, const nc::Scene& scene) {
  const nc::PackedGeometry packed = nc::pack_geometry(scene);
  std::vector<const nc::PositionBox*> box_of(scene.vertices.size(), nullptr);
  for (size_t p = 0; p < scene.primitives.size(); ++p)
    for (uint32_t k = 0; k < scene.primitives[p].index_count; ++k)
      box_of[size_t(scene.primitives[p].vertex_offset) + scene.indices[scene.primitives[p].first_index + k]] =
          &packed.boxes[p];
  table() << "\n## vertex streams: " << label << ", " << scene.vertices.size() << " vertices\n"
          << "position bits  bytes/vertex  max mm     mean mm    quantise ms\n";
  const uint32_t other_streams = nc::kVertexStreamBytes[nc::uv0_stream] + nc::kVertexStreamBytes[nc::frame_stream] +
                                 nc::kVertexStreamBytes[nc::color_uv1_stream];
  for (uint32_t bits : {8u, 10u, 12u, 16u}) {
    const uint32_t levels = (1u << bits) - 1;
    std::vector<double> times;
    double worst = 0, sum = 0;
    size_t counted = 0;
    for (int r = 0; r < 5; ++r) {
      worst = sum = 0;
      counted = 0;
      const double start = now_ms();
      for (size_t v = 0; v < scene.vertices.size(); ++v) {
        if (!box_of[v]) continue;
        const glm::vec3 step = nc::position_step(box_of[v]->min, box_of[v]->max, levels);
        glm::dvec3 error;
        for (int k = 0; k < 3; ++k) {
          const float p = scene.vertices[v].position[k], origin = box_of[v]->min[k];
          error[k] = nc::dequantise_position(nc::quantise_position(p, origin, step[k], levels), origin, step[k]) - p;
        }
        worst = std::max(worst, glm::length(error));
        sum += glm::length(error);
        ++counted;
      }
      times.push_back(now_ms() - start);
    }
    const uint32_t bytes = (bits <= 10 ? 4 : 8) + other_streams;
    const std::string row = "vertex_streams." + key + ".position_bits_" + std::to_string(bits);
    table() << std::setw(13) << bits << std::setw(14) << bytes << "  " << std::scientific << std::setprecision(3)
            << worst * 1e3 << "  " << sum / std::max<size_t>(counted, 1) * 1e3 << "  " << std::fixed
            << std::setprecision(3) << median(times) << "\n";
    figure(row + ".bytes_per_vertex", bytes);
    figure(row + ".max_mm", worst * 1e3);
    figure(row + ".mean_mm", sum / std::max<size_t>(counted, 1) * 1e3);
    figure(row + ".quantise_ms", median(times));
  }
  nc::GeometryHeader header;
  std::memcpy(&header, packed.bytes.data(), sizeof(header));
  const double vertex_bytes = double(header.index_offset - header.stream_offset[nc::position_stream]);
  const double float_layout = 72.0 * scene.vertices.size();
  const double float_buffer = nc::kGeometryAlignment +
                              std::ceil(float_layout / nc::kGeometryAlignment) * nc::kGeometryAlignment +
                              4.0 * scene.indices.size();
  std::vector<double> times;
  for (int r = 0; r < 5; ++r) {
    const double start = now_ms();
    const nc::PackedGeometry again = nc::pack_geometry(scene);
    times.push_back(now_ms() - start);
  }
  table() << "vertex streams " << std::setprecision(0) << vertex_bytes << " bytes (72-byte floats: " << float_layout
          << "), ratio " << std::setprecision(3) << vertex_bytes / float_layout << "; scene.geometry "
          << packed.bytes.size() << " bytes, ratio " << packed.bytes.size() / float_buffer << "; pack_geometry "
          << median(times) << " ms; G-buffer pass time: pass_ms." << key << ".gbuffer.opaque\n";
  figure("vertex_streams." + key + ".vertex_bytes_ratio", vertex_bytes / float_layout);
  figure("vertex_streams." + key + ".geometry_bytes_ratio", packed.bytes.size() / float_buffer);
  figure("vertex_streams." + key + ".pack_ms", median(times));
}

// motion.stencil: time against the dilation radius (timestamps and the isolated run's wall clock,
// as for depth.convert), and texels that differ from the brute-force CPU dilation of
// tests/reference/motion_mask_reference.h (the unit test requires none).
void bench_motion_stencil(nc::GpuDevice& gpu, nc::PipelineCache& cache, uint32_t width, uint32_t height) {
  std::mt19937 rng(11);
  const std::vector<uint8_t> tags = bench_tags(size_t(width) * height, rng);
  std::vector<uint8_t> depth_bytes(tags.size() * 5, 0);
  std::memcpy(depth_bytes.data() + tags.size() * 4, tags.data(), tags.size());
  const nc::IsolatedInput depth =
      image(VK_FORMAT_D32_SFLOAT_S8_UINT, nc::kinds::depth_stencil, width, height, depth_bytes);
  table() << "\n## motion.stencil (" << width << "x" << height << ", 1 pixel in 200 tagged)\n";
  for (int radius : {0, 2, 4, 8}) {
    std::vector<double> times, wall;
    nc::IsolatedRun run;
    for (int r = 0; r < 4; ++r) {  // the first run compiles the pipeline
      const double start = now_ms();
      run = nc::run_isolated(gpu, cache, nc::motion_stencil_pass(), {{"scene.depth", depth}},
                             {{"radius", double(radius)}}, width, height, nc::builtin_shaders());
      if (r > 0) wall.push_back(now_ms() - start);
      if (r > 0) times.push_back(gpu_ms(run));
    }
    const std::vector<uint8_t> expected = ref::motion_mask(tags, width, height, radius);
    const auto& mask = *run.outputs.at("motion.mask");
    size_t wrong = 0, masked = 0;
    for (size_t i = 0; i < expected.size(); ++i) {
      wrong += mask[i] != expected[i];
      masked += expected[i];
    }
    table() << "radius " << radius << "   gpu " << std::fixed << std::setprecision(3) << median(times)
            << " ms (timestamps), " << median(wall) << " ms isolated wall clock, " << std::setprecision(1)
            << 100.0 * double(masked) / double(expected.size()) << "% masked, " << wrong
            << " texels differ from the CPU dilation\n";
    const std::string row = "motion_stencil.radius" + std::to_string(radius);
    figure(row + ".gpu_ms", median(times));
    figure(row + ".isolated_wall_ms", median(wall));
    figure(row + ".mismatches", double(wrong));
  }
}

// decals.mesh and decals.projected against decal count on the reference scene of
// tests/reference/decal_reference.h: N projected boxes (the reference box, shifted and turned,
// grime) and N mesh decals (slabs on the ground), GPU ms as the median of `repeats` frames. The
// error figure is test 2's (tests/unit/decals_test.cpp): the largest distance between the box
// coordinate a coordinates decal writes into gbuffer.albedo and the ray-cast one, in metres along
// the box's axes, 10-bit quantisation included.
void bench_decals(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## decals (reference scene, " << width << "x" << height << ", median of " << repeats << ")\n"
          << std::left << std::setw(10) << "decals" << std::right << std::setw(18) << "decals.mesh ms" << std::setw(22)
          << "decals.projected ms\n";
  for (uint32_t count : {1u, 16u, 256u}) {
    nc::reference::DecalTestScene s = nc::reference::decal_test_scene();
    nc::scene_kit::Builder build(s.scene);
    nc::Material paint = nc::scene_kit::plain("decal.paint", {0.9f, 0.2f, 0.1f}, 0.0f, 0.5f, nc::stencil::plain);
    paint.base_color.a = 0.7f;
    paint.decal = true;
    const uint32_t slab = build.box({0.4f, 0.005f, 0.4f}, build.material(paint), 1.0f);
    std::mt19937 rng(count);
    std::uniform_real_distribution<double> spread(-4.0, 4.0), turn(0.0, 6.28);
    for (uint32_t k = 0; k < count; ++k) {
      nc::Decal decal;
      decal.world = glm::rotate(glm::translate(glm::dmat4(1.0), {spread(rng), 0.0, spread(rng)}), turn(rng),
                                glm::dvec3(0, 1, 0)) *
                    nc::reference::decal_test_box();
      decal.pattern = nc::DecalPattern::grime;
      decal.scale = 4.0f;
      s.scene.decals.push_back(decal);
      build.place(slab, {spread(rng), 0.005, spread(rng)}, turn(rng));
    }
    nc::RenderSettings settings;
    settings.width = width;
    settings.height = height;
    settings.path.motion = nc::CameraPath::Motion::still;
    nc::Renderer renderer(gpu, s.scene, settings);
    std::map<std::string, std::vector<double>> ms;
    for (int r = 0; r <= repeats; ++r) {
      const nc::RenderedFrame frame = renderer.render_frame(uint32_t(r), false);
      for (size_t i = 0; r > 0 && i < frame.graph.passes.size(); ++i)
        if (frame.graph.passes[i].runs)
          ms[frame.graph.passes[i].decl->name].push_back(frame.execution.passes[i].time_ms);
    }
    const double mesh = median(ms["decals.mesh"]), projected = median(ms["decals.projected"]);
    table() << std::left << std::setw(10) << count << std::right << std::fixed << std::setprecision(3) << std::setw(18)
            << mesh << std::setw(21) << projected << "\n";
    figure("decals_mesh_ms." + std::to_string(count), mesh);
    figure("decals_projected_ms." + std::to_string(count), projected);
    if (count == 256) {
      figure("decals_mesh_ms", mesh);
      figure("decals_projected_ms", projected);
    }
  }
  nc::reference::DecalTestScene s = nc::reference::decal_test_scene();
  nc::Decal decal;
  decal.world = nc::reference::decal_test_box();
  decal.pattern = nc::DecalPattern::coordinates;
  s.scene.decals.push_back(decal);
  nc::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.path.motion = nc::CameraPath::Motion::still;
  nc::Renderer renderer(gpu, s.scene, settings);
  const nc::RenderedFrame frame = renderer.render_frame(0, true);
  const auto& albedo = *frame.execution.final_version("gbuffer.albedo")->bytes;
  const glm::dvec3 size(glm::length(decal.world[0]), glm::length(decal.world[1]), glm::length(decal.world[2]));
  double worst = 0.0;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const auto hit = nc::reference::cast_pixel(s, frame.camera, width, height, x, y);
      if (!hit || hit->moving) continue;
      const glm::dvec3 local = nc::reference::decal_local(decal.world, hit->position);
      // Away from the faces (test 2's bound) and from silhouettes: one pixel's footprint.
      const double footprint = 2.0 * std::tan(double(frame.camera.yfov) / 2) / height * hit->distance;
      if (nc::reference::distance_to_faces(decal.world, hit->position) <= footprint ||
          !glm::all(glm::lessThanEqual(glm::abs(local), glm::dvec3(0.5))))
        continue;
      uint32_t word;
      std::memcpy(&word, albedo.data() + 4 * (size_t(y) * width + x), 4);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(((word >> (10 * c)) & 1023) / 1023.0 - (local[c] + 0.5)) * size[c]);
    }
  table() << "position error of a coordinates decal: " << std::setprecision(5) << worst * 1e3
          << " mm (10-bit quantisation of a " << size.x << " m box: " << 0.5 / 1023 * size.x * 1e3 << " mm)\n";
  figure("decals_position_error_m", worst);
}

}  // namespace nightcap::bench
