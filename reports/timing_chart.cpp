#include "reports/timing_chart.h"

#include <algorithm>
#include <map>
#include <set>
#include <sstream>

#include "reports/html.h"

namespace nightcap {

namespace {

std::string clock_legend(PassClock clock) {
  switch (clock) {
    case PassClock::device:
      return "the device's timestamps";
    case PassClock::host_alone:
      return "the host's clock, the pass submitted alone";
    case PassClock::host:
      break;
  }
  return "the host's clock (a CPU pass)";
}

}  // namespace

double pass_time_sum(const FrameRecord& frame) {
  double sum = 0.0;
  for (const PassRecord& p : frame.passes)
    if (p.ran) sum += p.time_ms;
  return sum;
}

std::string timing_chart_svg(const FrameRecord& frame) {
  constexpr int kLabelWidth = 190, kBarWidth = 420, kRow = 20, kTop = 24;
  double longest = 0.0;
  int rows = 0;
  std::set<PassClock> clocks;
  bool stamps_drawn = false;
  for (const PassRecord& p : frame.passes)
    if (p.ran) {
      const bool stamps = p.gpu_ms && p.clock != PassClock::device;
      longest = std::max({longest, p.time_ms, stamps ? *p.gpu_ms : 0.0});
      clocks.insert(p.clock);
      stamps_drawn |= stamps;
      ++rows;
    }
  const double scale = longest > 0 ? kBarWidth / longest : 0.0;
  const int height = kTop + rows * kRow + 8, width = kLabelWidth + kBarWidth + 150;
  std::ostringstream svg;
  svg << "<svg class=\"timings\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << width << " " << height << "\" role=\"img\" aria-label=\"pass timings\">\n"
      << "<text x=\"" << kLabelWidth << "\" y=\"14\" class=\"legend\"><tspan class=\"time\">■</tspan> ms";
  if (stamps_drawn) svg << "  <tspan class=\"stamps\">■</tspan> the device's timestamps";
  svg << "</text>\n";
  int row = 0;
  for (const PassRecord& p : frame.passes) {
    if (!p.ran) continue;
    const int y = kTop + row++ * kRow;
    const bool stamps = p.gpu_ms && p.clock != PassClock::device;
    svg << "<g><title>" << escape_markup(p.name) << ": " << format_number(p.time_ms, 3) << " ms by "
        << clock_legend(p.clock) << (stamps ? "; timestamps " + format_number(*p.gpu_ms, 3) + " ms" : "") << "</title>"
        << "<text x=\"" << kLabelWidth - 6 << "\" y=\"" << y + 12 << "\" text-anchor=\"end\">" << escape_markup(p.name)
        << "</text>"
        << "<rect class=\"time " << pass_clock_name(p.clock) << "\" x=\"" << kLabelWidth << "\" y=\"" << y + 2
        << "\" width=\"" << std::max(1.0, p.time_ms * scale) << "\" height=\"10\"/>";
    if (stamps)
      svg << "<rect class=\"stamps\" x=\"" << kLabelWidth << "\" y=\"" << y + 13 << "\" width=\""
          << std::max(1.0, *p.gpu_ms * scale) << "\" height=\"3\"/>";
    svg << "<text x=\"" << kLabelWidth + std::max(p.time_ms, stamps ? *p.gpu_ms : 0.0) * scale + 6 << "\" y=\""
        << y + 12 << "\">" << format_number(p.time_ms, 3) << " ms</text></g>\n";
  }
  svg << "</svg>\n";
  std::ostringstream caption;
  caption << "<p class=\"clocks\">Measured by ";
  bool first = true;
  for (PassClock clock : clocks) {
    caption << (first ? "" : "; ") << clock_legend(clock) << " (" << pass_clock_name(clock) << ")";
    first = false;
  }
  caption << ".</p>\n";
  return caption.str() + svg.str();
}

std::string frame_times_table(const CaptureManifest& manifest, const FrameRecord& shown,
                              const std::function<std::string(const std::string&)>& anchor_of) {
  if (manifest.frames.size() < 2) return "";
  // Rows in the order of the frame shown, then any pass only other frames have.
  std::vector<std::string> names;
  std::set<std::string> listed;
  for (const PassRecord& p : shown.passes)
    if (listed.insert(p.name).second) names.push_back(p.name);
  for (const FrameRecord& frame : manifest.frames)
    for (const PassRecord& p : frame.passes)
      if (listed.insert(p.name).second) names.push_back(p.name);
  std::vector<std::map<std::string, const PassRecord*>> by_name(manifest.frames.size());
  for (size_t f = 0; f < manifest.frames.size(); ++f)
    for (const PassRecord& p : manifest.frames[f].passes) by_name[f][p.name] = &p;

  std::ostringstream html;
  html << "<table class=\"frame-times\"><caption>Pass times of every recorded frame, ms</caption>\n<tr><th>pass</th>";
  for (const FrameRecord& frame : manifest.frames)
    html << "<th" << (frame.index == shown.index ? " class=\"shown\"" : "") << ">frame " << frame.index << "</th>";
  html << "</tr>\n";
  for (const std::string& name : names) {
    html << "<tr><th>";
    if (const std::string anchor = anchor_of(name); !anchor.empty())
      html << "<a href=\"#" << anchor << "\">" << escape_markup(name) << "</a>";
    else
      html << escape_markup(name);
    html << "</th>";
    for (size_t f = 0; f < manifest.frames.size(); ++f) {
      const auto it = by_name[f].find(name);
      if (it == by_name[f].end() || !it->second->ran)
        html << "<td class=\"not-run\"></td>";
      else
        html << "<td>" << format_number(it->second->time_ms, 3) << "</td>";
    }
    html << "</tr>\n";
  }
  html << "<tr class=\"sum\"><th>sum</th>";
  for (const FrameRecord& frame : manifest.frames) html << "<td>" << format_number(pass_time_sum(frame), 3) << "</td>";
  html << "</tr>\n<tr class=\"sum\"><th>frame wall clock</th>";
  for (const FrameRecord& frame : manifest.frames)
    html << "<td>" << (frame.wall_ms ? format_number(*frame.wall_ms, 3) : "") << "</td>";
  html << "</tr>\n</table>\n";
  return html.str();
}

}  // namespace nightcap
