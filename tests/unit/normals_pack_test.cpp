// normals.pack on lavapipe over 10⁷ directions (Fibonacci sphere + axes + octant diagonals),
// against the bounds of shared/design/accuracy.md: mean ≤ 0.03°, max ≤ the format's floor at
// the axes, atan(√2/255) ≈ 0.318°; every stored code decodes to a finite unit vector. The
// error is measured against the 10-bit G-buffer normal the pass reads (the method's own error).
#include <cmath>
#include <cstring>

#include "passes/gbuffer/kinds.h"
#include "passes/normals/bfn_lut.h"
#include "passes/normals/stage.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

using dvec3 = glm::dvec3;

double angle_degrees(const dvec3& a, const dvec3& b) {
  return glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
}

uint32_t pack_a2b10g10r10(const dvec3& n) {
  auto code = [](double v) { return uint32_t(std::lround((v * 0.5 + 0.5) * 1023.0)); };
  return code(n.x) | code(n.y) << 10 | code(n.z) << 20;
}

dvec3 unpack_a2b10g10r10(uint32_t w) {
  auto value = [](uint32_t c) { return c / 1023.0 * 2.0 - 1.0; };
  return glm::normalize(dvec3(value(w & 1023), value((w >> 10) & 1023), value((w >> 20) & 1023)));
}

std::vector<dvec3> test_directions(size_t count) {
  std::vector<dvec3> directions;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      dvec3 d(0.0);
      d[axis] = sign;
      directions.push_back(d);
    }
  for (int octant = 0; octant < 8; ++octant)
    directions.push_back(glm::normalize(dvec3(octant & 1 ? -1 : 1, octant & 2 ? -1 : 1, octant & 4 ? -1 : 1)));
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  const size_t fibonacci = count - directions.size();
  for (size_t i = 0; i < fibonacci; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / fibonacci;
    const double r = std::sqrt(1.0 - y * y);
    directions.push_back(dvec3(std::cos(golden * i) * r, y, std::sin(golden * i) * r));
  }
  return directions;
}

class NormalsPack : public GpuTest {};

TEST_F(NormalsPack, BestFitNormalsReachTheAccuracyBound) {
  const size_t count = 10'000'000;
  const uint32_t width = 4096, height = uint32_t((count + width - 1) / width);
  const std::vector<dvec3> directions = test_directions(count);
  std::vector<uint8_t> normals(size_t(width) * height * 4), material(size_t(width) * height * 4, 0);
  std::vector<dvec3> inputs(size_t(width) * height, dvec3(0, 0, 1));
  for (size_t i = 0; i < inputs.size(); ++i) {
    const uint32_t word = pack_a2b10g10r10(i < count ? directions[i] : dvec3(0, 0, 1));
    std::memcpy(normals.data() + 4 * i, &word, 4);
    inputs[i] = unpack_a2b10g10r10(word);
    material[4 * i + 1] = uint8_t(i % 256);  // roughness rides along in alpha
  }
  const uint32_t lut_size = 1024;
  std::vector<uint8_t> lut = build_bfn_lut(lut_size);
  const IsolatedRun result =
      run(normals_pack_pass(),
          {{"gbuffer.normal", image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, kinds::normal, width, height, normals)},
           {"gbuffer.material", image(VK_FORMAT_R8G8B8A8_UNORM, kinds::material, width, height, material)},
           {"normals.bfn_lut", image(VK_FORMAT_R8_UINT, kinds::lookup_table, lut_size, lut_size, lut)}},
          width, height);
  const std::vector<uint8_t>& packed = *result.outputs.at("normals.packed");

  double sum = 0, worst = 0, plain_sum = 0, plain_worst = 0;
  for (size_t i = 0; i < count; ++i) {
    const uint8_t* c = packed.data() + 4 * i;
    const dvec3 stored(decode_signed8(c[0]), decode_signed8(c[1]), decode_signed8(c[2]));
    ASSERT_GT(glm::length(stored), 0.0) << "direction " << i << " stored as the zero vector";
    const double error = angle_degrees(glm::normalize(stored), inputs[i]);
    ASSERT_TRUE(std::isfinite(error));
    sum += error;
    worst = std::max(worst, error);
    ASSERT_EQ(c[3], uint8_t(i % 256)) << "roughness not carried in alpha";
    const dvec3 plain(decode_signed8(encode_unorm8(float(inputs[i].x))),
                      decode_signed8(encode_unorm8(float(inputs[i].y))),
                      decode_signed8(encode_unorm8(float(inputs[i].z))));
    const double plain_error = angle_degrees(glm::normalize(plain), inputs[i]);
    plain_sum += plain_error;
    plain_worst = std::max(plain_worst, plain_error);
  }
  const double mean = sum / count;
  const double axis_floor = glm::degrees(std::atan(std::sqrt(2.0) / 255.0));
  std::printf("normals.pack over %zu directions: mean %.4f deg, max %.4f deg (plain 8-bit: mean %.4f, max %.4f)\n",
              count, mean, worst, plain_sum / count, plain_worst);
  EXPECT_LE(mean, 0.03);
  EXPECT_LE(worst, axis_floor + 1e-9);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
