// taa: what it costs in the street frame, and time against error for its history length and its
// clipping, against the same still frame supersampled (tests/reference/taa_reference.h).
#include <iomanip>
#include <string>
#include <vector>

#include "passes/assembly/renderer.h"
#include "passes/taa/taa.glsl.h"
#include "tests/bench/bench_common.h"
#include "tests/bench/benchmarks.h"
#include "tests/reference/taa_reference.h"

namespace nc = nightcap;

namespace nightcap::bench {

// On against off (`--set taa.enabled=0`: no jitter, lighting.lit copied unresolved) in the frame
// frame_ms_street measures, the map's street shot walking, alternating (taa_on_off_ratio).
//
// Time against error: 32 still frames of the street shot (cars and pedestrians stopped) at
// 640×360, final.ldr of the last against the frame supersampled with 256 samples (PSNR of the
// 8-bit codes and LDR-FLIP), and taa's time (alone, the median of frames 1..31), for history
// lengths and, with still pixels clipped too (clip_still), the two boxes; "off" is the frame
// without TAA.
void bench_taa(nc::GpuDevice& gpu, uint32_t width, uint32_t height, int repeats) {
  table() << "\n## TAA, map street shot at " << width << "x" << height << " (median of " << repeats
          << " alternating frames)\n";
  const nc::Scene scene = nc::build_map({1, 16.0, nc::Shot::street});
  street_on_off(gpu, scene, width, height, repeats, "taa", "taa_on_off_ratio", "taa");

  const nc::Scene still = nc::frozen(scene);
  const nc::RenderSettings settings = still_street_settings();
  const uint32_t frames = 32;
  const std::vector<uint8_t> reference = test::final_of_resolved(
      gpu, still, settings, frames - 1, nc::supersampled_lit(gpu, still, test::still_settings(settings, 1), 16));
  struct Variant {
    std::string key;
    double enabled = 1, history = 16, clip_still = 0, clip = kTaaClipVariance;
  };
  // Under a still camera only the history length and clip_still change what the resolve does.
  const std::vector<Variant> variants = {{"off", 0},
                                         {"frames4", 1, 4},
                                         {"frames8", 1, 8},
                                         {"frames16", 1, 16},
                                         {"frames32", 1, 32},
                                         {"clip_still.variance", 1, 16, 1, kTaaClipVariance},
                                         {"clip_still.minmax", 1, 16, 1, kTaaClipMinMax}};
  table() << "640x360, " << frames << " still frames against 256 samples\n"
          << "variant                taa ms   PSNR dB   LDR-FLIP\n";
  for (const Variant& v : variants) {
    nc::RenderSettings s = test::still_settings(settings, frames);
    s.params["taa"]["enabled"] = v.enabled;
    s.params["taa"]["frames"] = v.history;
    s.params["taa"]["clip"] = v.clip;
    s.params["taa"]["clip_still"] = v.clip_still;
    nc::Renderer renderer(gpu, still, s);
    std::vector<double> ms;
    std::vector<uint8_t> last;
    for (uint32_t k = 0; k < frames; ++k) {
      const nc::RenderedFrame frame = renderer.render_frame(k, false);
      if (k > 0) ms.push_back(frame_pass_ms(frame, "taa"));
      if (k + 1 == frames) last = *frame.execution.final_version("final.ldr")->bytes;
    }
    const double psnr = test::psnr_rgb8(reference, last), flip = test::flip_mean_srgb8(reference, last, 640, 360);
    table() << std::left << std::setw(22) << v.key << std::right << std::fixed << std::setw(7) << std::setprecision(2)
            << median(ms) << std::setw(10) << psnr << std::setw(11) << std::setprecision(4) << flip
            << (v.key == "frames16" ? "   (default)" : "") << "\n";
    figure("taa_ms." + v.key, median(ms));
    figure("taa_psnr_db." + v.key, psnr);
    figure("taa_flip." + v.key, flip);
  }
}

}  // namespace nightcap::bench
