// The report's graphs (reports/frame_graphs.h): the overview has a node per pass, a cluster per
// stage, and every in-page link of it, and of the page, lands on the section it names in
// Chromium; each pass's section has its own graph naming what it read and wrote.
#include <gtest/gtest.h>

#include <regex>
#include <set>

#include "tests/e2e/browser.h"
#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

const char* kCity = "--city-block --size 320x180 --frames 2";  // as tests/e2e/report_test.cpp

struct Report {
  nlohmann::json frame;
  fs::path index;
  std::string html;
};

Report report(const std::string& name) {
  const fs::path capture = shared_capture("city", kCity);
  const fs::path out = scratch("report-graph") / name;
  const CliResult r = run_cli("report " + quote(capture) + " -o " + quote(out));
  EXPECT_EQ(r.code, 0) << r.err;
  return {read_json(capture / "manifest.json").at("frames")[0], out / "index.html", slurp(out / "index.html")};
}

// The part of the page between `from` and the next `to`.
std::string between(const std::string& html, const std::string& from, const std::string& to) {
  const size_t start = html.find(from);
  if (start == std::string::npos) return "";
  return html.substr(start, html.find(to, start) - start);
}

TEST(ReportGraph, TheOverviewHasANodeLinkedToEveryPassAndAClusterPerStage) {
  const Report r = report("overview");
  const std::string overview = between(r.html, "<div class=\"overview\">", "</section>");
  ASSERT_NE(overview.find("<svg"), std::string::npos);
  std::set<std::string> stages;
  for (size_t i = 0; i < r.frame.at("passes").size(); ++i) {
    const nlohmann::json& p = r.frame.at("passes")[i];
    stages.insert(p.at("stage").get<std::string>());
    EXPECT_NE(overview.find("xlink:href=\"#pass-" + std::to_string(i) + "\""), std::string::npos) << p.at("name");
    EXPECT_NE(overview.find(">" + p.at("name").get<std::string>() + "</text>"), std::string::npos) << p.at("name");
  }
  static const std::regex cluster(
      R"re(<g id="clust\d+" class="cluster">\s*<title>[^<]*</title>\s*<[^>]*>\s*<text[^>]*>([^<]+)</text>)re");
  std::set<std::string> clusters;
  for (auto it = std::sregex_iterator(overview.begin(), overview.end(), cluster); it != std::sregex_iterator(); ++it)
    clusters.insert((*it)[1]);
  EXPECT_EQ(clusters, stages);
  EXPECT_TRUE(fs::is_regular_file(r.index.parent_path() / "graph.svg")) << "the whole graph, linked from the page";
}

TEST(ReportGraph, EachPassSectionHasItsOwnGraphOfWhatItReadAndWrote) {
  const Report r = report("passes");
  for (size_t i = 0; i < r.frame.at("passes").size(); ++i) {
    const nlohmann::json& p = r.frame.at("passes")[i];
    const std::string section = between(r.html, "id=\"pass-" + std::to_string(i) + "\"", "</section>");
    const std::string graph = between(section, "<div class=\"pass-graph\">", "</div>");
    if (p.at("inputs").empty() && p.at("outputs").empty()) {
      EXPECT_TRUE(graph.empty()) << p.at("name");
      continue;
    }
    ASSERT_NE(graph.find("<svg"), std::string::npos) << p.at("name");
    for (const char* side : {"inputs", "outputs"})
      for (const auto& resource : p.at(side))
        EXPECT_NE(graph.find(">" + resource.at("resource").get<std::string>() + "</text>"), std::string::npos)
            << p.at("name") << " " << side << " " << resource.at("resource");
  }
}

// In Chromium: every link of the page to an anchor in it (the overview's nodes are SVG links)
// lands on an element, and each of the overview's lands on the section of the pass it names.
TEST(ReportGraph, EveryInPageLinkLandsOnAnExistingSection) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const Report r = report("links");
  const char* script = R"js((() => {
    const xlink = "http://www.w3.org/1999/xlink";
    const target = (a) => a.getAttribute("href") || a.getAttributeNS(xlink, "href") || "";
    const links = [...document.querySelectorAll("a")].filter((a) => target(a).startsWith("#"));
    const broken = links.filter((a) => !document.getElementById(target(a).slice(1))).map(target);
    const overview = [...document.querySelectorAll(".overview a")].filter((a) => target(a).startsWith("#"));
    const mismatched = overview.filter((a) => {
      const section = document.getElementById(target(a).slice(1));
      const name = a.querySelector("text");
      return !section || !name || section.dataset.pass !== name.textContent;
    }).map(target);
    return { links: links.length, overview: overview.length, broken, mismatched };
  })())js";
  const PageCheck page = check_page(r.index, scratch("report-graph-browser"), script);
  EXPECT_TRUE(page.console_errors.empty()) << page.console_errors.front();
  const nlohmann::json& result = page.script_result;
  ASSERT_TRUE(result.is_object()) << result.dump();
  EXPECT_EQ(result.at("overview").get<size_t>(), r.frame.at("passes").size());
  EXPECT_GT(result.at("links").get<size_t>(), 2 * r.frame.at("passes").size()) << "the list, the overview, the table";
  EXPECT_TRUE(result.at("broken").empty()) << result.dump();
  EXPECT_TRUE(result.at("mismatched").empty()) << result.dump();
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
