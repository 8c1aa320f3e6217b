// ao: what the AO chain costs in the street frame, and time against error for its slices, steps,
// filter and the frame's size against Monte Carlo AO through the depth buffer
// (tests/reference/ao_reference.h).
#include <cmath>
#include <cstring>
#include <deque>
#include <iomanip>
#include <string>
#include <vector>

#include "compare/decoded_image.h"
#include "passes/ao/stage.h"
#include "passes/assembly/renderer.h"
#include "passes/assembly/supersample.h"
#include "passes/core/format.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/ao_reference.h"
#include "tests/reference/taa_reference.h"

namespace nc = nightcap;

namespace nightcap::bench {
namespace {

// The values of an image the frame ended with, its format's channels a texel.
std::vector<float> decoded(const nc::RenderedFrame& frame, const std::string& resource) {
  const nc::VersionData& v = *frame.execution.final_version(resource);
  const nc::FormatInfo format = *nc::format_info(v.desc.format);
  const uint64_t texels = uint64_t(v.desc.extent.width) * v.desc.extent.height;
  std::vector<float> values(texels * nc::aspect_channels(format, 0));
  nc::decode_values(format, 0, std::span(*v.bytes).first(texels * format.texel_bytes), values.data());
  return values;
}

// Time and error of the chain at one set of parameters and one size: 8 still frames, ao.bent of
// the last against the Monte Carlo reference, the chain's three passes timed alone (the median of
// frames 1..6).
struct ChainResult {
  double ms, mean, rms, p99, degrees;
  size_t samples;
};
struct ChainVariant {
  std::string key;
  double slices, steps, filter_radius;
  uint32_t width = 640, height = 360;
};
class StillStreet {
 public:
  StillStreet(nc::GpuDevice& gpu, const nc::Scene& still) : gpu_(gpu), still_(still) {}

  ChainResult measure(const ChainVariant& v) {
    constexpr uint32_t kFrames = 8;
    nc::RenderSettings s = test::still_settings(still_street_settings(), kFrames);
    s.width = v.width;
    s.height = v.height;
    s.params["ao.gtao"]["slices"] = v.slices;
    s.params["ao.gtao"]["steps"] = v.steps;
    s.params["ao.filter"]["radius"] = v.filter_radius;
    nc::Renderer renderer(gpu_, still_, s);
    std::vector<double> ms;
    for (uint32_t k = 0; k + 1 < kFrames; ++k) {
      const nc::RenderedFrame frame = renderer.render_frame(k, false);
      if (k > 0)
        ms.push_back(frame_pass_ms(frame, "ao.gtao") + frame_pass_ms(frame, "ao.filter") +
                     frame_pass_ms(frame, "ao.temporal"));
    }
    // The last frame is read back for the reference, and not timed.
    const nc::RenderedFrame frame = renderer.render_frame(kFrames - 1, true);
    const Reference& r = reference_of(frame, v.width, v.height);
    const reference::AoErrors e = reference::ao_errors(r.frame, r.samples, decoded(frame, "ao.bent"));
    double squares = 0;
    for (double error : e.visibility) squares += error * error;
    return {median(ms),
            reference::AoErrors::mean(e.visibility),
            std::sqrt(squares / e.visibility.size()),
            reference::AoErrors::percentile(e.visibility, 0.99),
            reference::AoErrors::mean(e.degrees),
            r.samples.size()};
  }

 private:
  struct Reference {
    reference::AoFrame frame;
    std::vector<reference::AoSample> samples;
  };
  // The depth and normals depend on the size only: one reference for each.
  const Reference& reference_of(const nc::RenderedFrame& frame, uint32_t width, uint32_t height) {
    for (const Reference& r : references_)
      if (r.frame.width == width && r.frame.height == height) return r;
    Reference& r = references_.emplace_back();
    std::memcpy(&r.frame.view, frame.execution.final_version("frame.views")->bytes->data(), sizeof r.frame.view);
    r.frame.width = width;
    r.frame.height = height;
    r.frame.depth = decoded(frame, "depth.linear");
    r.frame.half_depth = decoded(frame, "depth.half");
    r.frame.half_normals = decoded(frame, "normals.half");
    for (const nc::CompiledPass& pass : frame.graph.passes)
      if (pass.decl->name == "ao.gtao") {
        r.frame.radius = pass.params.at("radius");
        r.frame.falloff = pass.params.at("falloff");
        r.frame.thickness = reference::AoFrame::slab_depth(pass.params.at("thickness"));
      }
    r.samples = reference::monte_carlo_ao(r.frame);
    return r;
  }

  nc::GpuDevice& gpu_;
  const nc::Scene& still_;
  std::deque<Reference> references_;
};

// The results' rows, each marked when on the Pareto front: no other is both faster and nearer in
// RMS (the minimum mean squared error, as XeGTAO's authors tuned theirs against 512-sample
// ray-traced AO).
void print_front(const std::vector<ChainVariant>& variants, const std::vector<ChainResult>& results,
                 const std::string& default_key) {
  table() << "variant                    chain ms   mean err   RMS err   p99 err   bent °   front\n";
  for (size_t i = 0; i < variants.size(); ++i) {
    const ChainResult& r = results[i];
    bool front = true;
    for (const ChainResult& other : results)
      if (other.ms < r.ms && other.rms < r.rms) front = false;
    const std::string& key = variants[i].key;
    table() << std::left << std::setw(26) << key << std::right << std::fixed << std::setprecision(2) << std::setw(9)
            << r.ms << std::setprecision(4) << std::setw(11) << r.mean << std::setw(10) << r.rms << std::setw(10)
            << r.p99 << std::setprecision(2) << std::setw(9) << r.degrees << std::setw(8) << (front ? "yes" : "")
            << (key == default_key ? "   (default)" : "") << "\n";
    figure("ao_ms." + key, r.ms);
    figure("ao_mean_error." + key, r.mean);
    figure("ao_rms_error." + key, r.rms);
    figure("ao_p99_error." + key, r.p99);
    figure("ao_bent_degrees." + key, r.degrees);
    figure("ao_on_front." + key, front ? 1 : 0);
  }
}

}  // namespace

// On against off (`--set ao.enabled=0`: the three passes skipped, ao.bent unoccluded) in the
// frame frame_ms_street measures, the map's street shot walking, alternating (ao_on_off_ratio).
//
// Time against error: 8 still frames of the street shot (cars and pedestrians stopped),
// ao.bent of the last against the Monte Carlo reference at every 4th half texel whose radius
// lies on screen (mean and 99th percentile of |visibility error|), and the chain's time, over
// slices, steps and the filter's radius (0: unfiltered) at 640×360; then the defaults at the
// frame sizes around it, each against the reference through its own depth buffer (the chain
// runs at half the frame's resolution: frame.md).
void bench_ao(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## AO, map street shot at " << width << "x" << height << " (median of " << repeats
          << " alternating frames)\n";
  const nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
  street_on_off(gpu, scene, width, height, repeats, "ao", "ao_on_off_ratio", "ao");

  const nc::Scene still = nc::frozen(scene);
  StillStreet street(gpu, still);
  const auto default_of = [](const nc::PassDecl& pass, const std::string& param) {
    return pass.find_param(param)->default_value;
  };
  const double slices = default_of(nc::ao_gtao_pass(), "slices"), steps = default_of(nc::ao_gtao_pass(), "steps"),
               filter = default_of(nc::ao_filter_pass(), "radius");
  const std::string default_key = "slices" + std::to_string(int(slices)) + ".steps" + std::to_string(int(steps)) +
                                  ".filter" + std::to_string(int(filter));
  const std::vector<ChainVariant> variants = {{"slices1.steps2.filter2", 1, 2, 2}, {"slices2.steps4.filter1", 2, 4, 1},
                                              {"slices2.steps8.filter1", 2, 8, 1}, {"slices3.steps4.filter0", 3, 4, 0},
                                              {"slices3.steps4.filter1", 3, 4, 1}, {"slices3.steps4.filter2", 3, 4, 2},
                                              {"slices3.steps8.filter0", 3, 8, 0}, {"slices3.steps8.filter1", 3, 8, 1},
                                              {"slices3.steps8.filter2", 3, 8, 2}, {"slices6.steps8.filter1", 6, 8, 1}};
  std::vector<ChainResult> results;
  for (const ChainVariant& v : variants) results.push_back(street.measure(v));
  table() << "640x360, ao.bent after 8 still frames against Monte Carlo (" << results.front().samples
          << " half texels, 512 directions)\n";
  print_front(variants, results, default_key);

  std::vector<ChainVariant> sizes;
  for (const auto& [w, h] : {std::pair{320u, 180u}, std::pair{640u, 360u}, std::pair{1280u, 720u}})
    sizes.push_back({default_key + ".size" + std::to_string(w) + "x" + std::to_string(h), slices, steps, filter, w, h});
  std::vector<ChainResult> by_size;
  table() << "the defaults by frame size, each against Monte Carlo through its own depth buffer (";
  for (const ChainVariant& v : sizes) {
    by_size.push_back(street.measure(v));
    table() << (by_size.size() > 1 ? ", " : "") << by_size.back().samples << " half texels";
  }
  table() << ")\n";
  print_front(sizes, by_size, default_key + ".size640x360");
}

}  // namespace nightcap::bench
