#include "reports/timing_chart.h"

#include <algorithm>
#include <sstream>

#include "reports/html.h"

namespace nightcap {

std::string timing_chart_svg(const FrameRecord& frame) {
  constexpr int kLabelWidth = 190, kBarWidth = 420, kRow = 20, kTop = 24;
  double longest = 0.0;
  int rows = 0;
  for (const PassRecord& p : frame.passes)
    if (p.ran) {
      longest = std::max({longest, p.gpu_ms.value_or(0.0), p.cpu_ms});
      ++rows;
    }
  const double scale = longest > 0 ? kBarWidth / longest : 0.0;
  const int height = kTop + rows * kRow + 8, width = kLabelWidth + kBarWidth + 150;
  std::ostringstream svg;
  svg << "<svg class=\"timings\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << width << " " << height << "\" role=\"img\" aria-label=\"pass timings\">\n"
      << "<text x=\"" << kLabelWidth << "\" y=\"14\" class=\"legend\"><tspan class=\"gpu\">■</tspan> GPU ms  "
      << "<tspan class=\"cpu\">■</tspan> CPU ms (recording)</text>\n";
  int row = 0;
  for (const PassRecord& p : frame.passes) {
    if (!p.ran) continue;
    const int y = kTop + row++ * kRow;
    const double gpu = p.gpu_ms.value_or(0.0);
    svg << "<g><title>" << escape_markup(p.name) << ": " << (p.gpu_ms ? "GPU " + format_number(gpu, 3) + " ms, " : "")
        << "CPU " << format_number(p.cpu_ms, 3) << " ms</title>"
        << "<text x=\"" << kLabelWidth - 6 << "\" y=\"" << y + 12 << "\" text-anchor=\"end\">" << escape_markup(p.name)
        << "</text>";
    if (p.gpu_ms)
      svg << "<rect class=\"gpu\" x=\"" << kLabelWidth << "\" y=\"" << y + 2 << "\" width=\""
          << std::max(1.0, gpu * scale) << "\" height=\"10\"/>";
    svg << "<rect class=\"cpu\" x=\"" << kLabelWidth << "\" y=\"" << y + 13 << "\" width=\""
        << std::max(1.0, p.cpu_ms * scale) << "\" height=\"4\"/>"
        << "<text x=\"" << kLabelWidth + std::max(gpu, p.cpu_ms) * scale + 6 << "\" y=\"" << y + 12 << "\">"
        << (p.gpu_ms ? format_number(gpu, 3) : "CPU " + format_number(p.cpu_ms, 3)) << " ms</text></g>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace nightcap
