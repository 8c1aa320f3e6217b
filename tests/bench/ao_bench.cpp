// ao: what the AO chain costs in the street frame, and time against error for its slices, steps
// and filter against Monte Carlo AO through the depth buffer (tests/reference/ao_reference.h).
#include <cmath>
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

}  // namespace

// On against off (`--set ao.enabled=0`: the three passes skipped, ao.bent unoccluded) in the
// frame frame_ms_street measures, the map's street shot walking, alternating (ao_on_off_ratio).
//
// Time against error: 8 still frames of the street shot (cars and pedestrians stopped) at
// 640×360; ao.bent of the last against the Monte Carlo reference at every 4th half texel whose
// radius lies on screen (mean and 99th percentile of |visibility error|), and the chain's time
// (ao.gtao + ao.filter + ao.temporal, each alone, the median of frames 1..6), over slices, steps
// and the filter's radius (0: unfiltered). The chain runs at half resolution only (frame.md).
// A variant is on the Pareto front when no other is both faster and nearer in RMS (the minimum
// mean squared error, as XeGTAO's authors tuned theirs against 512-sample ray-traced AO).
void bench_ao(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## AO, map street shot at " << width << "x" << height << " (median of " << repeats
          << " alternating frames)\n";
  const nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
  street_on_off(gpu, scene, width, height, repeats, "ao", "ao_on_off_ratio", "ao");

  const nc::Scene still = nc::frozen(scene);
  const nc::RenderSettings settings = still_street_settings();
  const uint32_t frames = 8;
  struct Variant {
    std::string key;
    double slices, steps, filter_radius;
  };
  const std::vector<Variant> variants = {{"slices1.steps2.filter2", 1, 2, 2}, {"slices2.steps4.filter1", 2, 4, 1},
                                         {"slices2.steps8.filter1", 2, 8, 1}, {"slices3.steps4.filter0", 3, 4, 0},
                                         {"slices3.steps4.filter1", 3, 4, 1}, {"slices3.steps4.filter2", 3, 4, 2},
                                         {"slices3.steps8.filter0", 3, 8, 0}, {"slices3.steps8.filter1", 3, 8, 1},
                                         {"slices3.steps8.filter2", 3, 8, 2}, {"slices6.steps8.filter1", 6, 8, 1}};
  const auto default_of = [](const nc::PassDecl& pass, const std::string& param) {
    return std::to_string(int(pass.find_param(param)->default_value));
  };
  const std::string default_key = "slices" + default_of(nc::ao_gtao_pass(), "slices") + ".steps" +
                                  default_of(nc::ao_gtao_pass(), "steps") + ".filter" +
                                  default_of(nc::ao_filter_pass(), "radius");
  struct Result {
    double ms, mean, rms, p99, degrees;
  };
  std::vector<Result> results;
  reference::AoFrame reference_frame;
  std::vector<reference::AoSample> samples;
  for (const Variant& v : variants) {
    nc::RenderSettings s = test::still_settings(settings, frames);
    s.params["ao.gtao"]["slices"] = v.slices;
    s.params["ao.gtao"]["steps"] = v.steps;
    s.params["ao.filter"]["radius"] = v.filter_radius;
    nc::Renderer renderer(gpu, still, s);
    std::vector<double> ms;
    for (uint32_t k = 0; k < frames; ++k) {
      // The last frame is read back for the reference, and not timed.
      const nc::RenderedFrame frame = renderer.render_frame(k, k + 1 == frames);
      if (k > 0 && k + 1 < frames)
        ms.push_back(frame_pass_ms(frame, "ao.gtao") + frame_pass_ms(frame, "ao.filter") +
                     frame_pass_ms(frame, "ao.temporal"));
      if (k + 1 < frames) continue;
      if (samples.empty()) {  // the depth and normals do not depend on the variant
        std::memcpy(&reference_frame.view, frame.execution.final_version("frame.views")->bytes->data(),
                    sizeof reference_frame.view);
        reference_frame.width = settings.width;
        reference_frame.height = settings.height;
        reference_frame.depth = decoded(frame, "depth.linear");
        reference_frame.half_depth = decoded(frame, "depth.half");
        reference_frame.half_normals = decoded(frame, "normals.half");
        for (const nc::CompiledPass& pass : frame.graph.passes)
          if (pass.decl->name == "ao.gtao") {
            reference_frame.radius = pass.params.at("radius");
            reference_frame.falloff = pass.params.at("falloff");
          }
        samples = reference::monte_carlo_ao(reference_frame);
      }
      const reference::AoErrors e = reference::ao_errors(reference_frame, samples, decoded(frame, "ao.bent"));
      double squares = 0;
      for (double error : e.visibility) squares += error * error;
      results.push_back({median(ms), reference::AoErrors::mean(e.visibility), std::sqrt(squares / e.visibility.size()),
                         reference::AoErrors::percentile(e.visibility, 0.99), reference::AoErrors::mean(e.degrees)});
    }
  }
  table() << "640x360, ao.bent after " << frames << " still frames against Monte Carlo (" << samples.size()
          << " half texels, 512 directions)\n"
          << "variant                    chain ms   mean err   RMS err   p99 err   bent °   front\n";
  for (size_t i = 0; i < variants.size(); ++i) {
    const Result& r = results[i];
    bool front = true;
    for (const Result& other : results)
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

}  // namespace nightcap::bench
