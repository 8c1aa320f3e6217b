// The report's timings (reports/timing_chart.h): the header and the timing section give the
// passes' times against the frame's wall clock, the chart a bar per pass that ran as long as its
// recorded time, and a capture of several frames a table of every frame's pass times whose
// cells are the manifest's.
#include <gtest/gtest.h>

#include <regex>

#include "reports/html.h"
#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const char* kCity = "--city-block --size 320x180 --frames 2";  // as tests/e2e/report_test.cpp
const char* kSmall = "--city-block --size 64x36";

std::string report_of(const fs::path& capture, const std::string& name) {
  const fs::path out = scratch("report-timings") / name;
  const CliResult r = run_cli("report " + quote(capture) + " -o " + quote(out));
  EXPECT_EQ(r.code, 0) << r.err;
  return slurp(out / "index.html");
}

TEST(ReportTimings, TheHeaderAndChartGiveEachPassesRecordedTimeAgainstTheWallClock) {
  const fs::path capture = shared_capture("city", kCity);
  const nlohmann::json frame = read_json(capture / "manifest.json").at("frames")[0];
  const std::string html = report_of(capture, "city");
  double sum = 0.0;
  std::map<std::string, double> times;
  for (const auto& p : frame.at("passes"))
    if (p.at("status") == "ran") {
      sum += p.at("time_ms").get<double>();
      times[p.at("name")] = p.at("time_ms").get<double>();
    }
  EXPECT_NE(html.find("passes " + format_number(sum, 3) + " ms of the frame's " +
                      format_number(frame.at("wall_ms").get<double>(), 3) + " ms wall clock"),
            std::string::npos);
  // One bar per pass that ran, its width proportional to its time: the longest fills the chart.
  static const std::regex bar(
      R"re(<title>([^<:]+): ([0-9.e+-]+) ms by [^<]*</title>.*?<rect class="time [a-z-]+" x="\d+" y="\d+" width="([0-9.e+-]+)")re");
  std::map<std::string, double> widths;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), bar); it != std::sregex_iterator(); ++it)
    widths[(*it)[1]] = std::stod((*it)[3]);
  ASSERT_EQ(widths.size(), times.size());
  double longest = 0.0;
  for (const auto& [name, ms] : times) longest = std::max(longest, ms);
  for (const auto& [name, ms] : times) EXPECT_NEAR(widths.at(name), std::max(1.0, ms / longest * 420.0), 0.01) << name;
  EXPECT_NE(html.find("the host's clock, the pass submitted alone (host-alone)"), std::string::npos);
}

TEST(ReportTimings, SeveralFramesGetATableOfEveryFramesPassTimes) {
  const fs::path capture = shared_capture("city", kCity);
  const nlohmann::json frames = read_json(capture / "manifest.json").at("frames");
  const std::string html = report_of(capture, "frames");
  const size_t table = html.find("<table class=\"frame-times\">");
  ASSERT_NE(table, std::string::npos);
  const std::string rows = html.substr(table, html.find("</table>", table) - table);
  for (const auto& p : frames[0].at("passes")) {
    const std::string name = p.at("name");
    const size_t row = rows.find(">" + escape_markup(name) + "</a></th>");
    ASSERT_NE(row, std::string::npos) << name;
    std::string expected;
    for (const auto& frame : frames)
      for (const auto& q : frame.at("passes"))
        if (q.at("name") == name)
          expected += q.at("status") == "ran" ? "<td>" + format_number(q.at("time_ms").get<double>(), 3) + "</td>"
                                              : "<td class=\"not-run\"></td>";
    EXPECT_EQ(rows.substr(rows.find("</th>", row) + 5, expected.size()), expected) << name;
  }
  EXPECT_NE(rows.find("<th>frame wall clock</th>"), std::string::npos);
}

TEST(ReportTimings, OneFrameGetsNoTable) {
  const std::string html = report_of(shared_capture("city-small", kSmall), "one");
  EXPECT_EQ(html.find("frame-times"), std::string::npos);
  EXPECT_NE(html.find("The passes that ran add up to"), std::string::npos);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
