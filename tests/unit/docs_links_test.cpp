// Every relative link and image of README.md and docs/ resolves to a file of the repository, and
// a link's #anchor to a heading of the page it names (GitHub's heading ids). Paths outside the
// repository (../shared/...) are no links: they are kept as plain text.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "tests/unit/text_lines.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace fs = std::filesystem;

const fs::path kRoot = fs::weakly_canonical(NIGHTCAP_SOURCE);

std::vector<fs::path> markdown_pages() {
  std::vector<fs::path> pages = {kRoot / "README.md"};
  for (const auto& entry : fs::recursive_directory_iterator(kRoot / "docs"))
    if (entry.is_regular_file() && entry.path().extension() == ".md") pages.push_back(entry.path());
  return pages;
}

bool is_fence(const std::string& line) { return line.rfind("```", 0) == 0; }

// The text outside fenced blocks and inline code, where a link is a link.
std::vector<std::string> prose_lines(const fs::path& page) {
  std::vector<std::string> prose;
  bool fenced = false;
  for (const std::string& line : lines_of(page)) {
    if (is_fence(line)) {
      fenced = !fenced;
      continue;
    }
    if (fenced) continue;
    static const std::regex code_span("`[^`]*`");
    prose.push_back(std::regex_replace(line, code_span, ""));
  }
  return prose;
}

// GitHub's id of a heading: lower case, spaces to '-', every other character but ASCII letters,
// digits, '-' and '_' dropped (GitHub keeps other letters too; these headings have none); a
// repeated id gets -1, -2, ...
std::set<std::string> heading_ids(const fs::path& page) {
  std::set<std::string> ids;
  std::map<std::string, int> seen;
  bool fenced = false;
  for (const std::string& line : lines_of(page)) {
    if (is_fence(line)) fenced = !fenced;
    if (fenced || line.rfind('#', 0) != 0) continue;
    const size_t text = line.find_first_not_of('#');
    if (text == std::string::npos || line[text] != ' ') continue;
    std::string id;
    for (const char c : line.substr(text + 1)) {
      const unsigned char u = static_cast<unsigned char>(c);
      if (std::isalnum(u) || c == '-' || c == '_') id += char(std::tolower(u));
      if (c == ' ') id += '-';
    }
    const int repeats = seen[id]++;
    ids.insert(repeats == 0 ? id : id + "-" + std::to_string(repeats));
  }
  return ids;
}

struct Link {
  fs::path page;
  std::string target;
};

std::vector<Link> relative_links() {
  std::vector<Link> links;
  // [text](target) and ![alt](target), an optional "title" after the target.
  static const std::regex link(R"(\]\(([^)\s]+)(\s+"[^"]*")?\))");
  for (const fs::path& page : markdown_pages())
    for (const std::string& line : prose_lines(page))
      for (auto it = std::sregex_iterator(line.begin(), line.end(), link); it != std::sregex_iterator(); ++it) {
        const std::string target = (*it)[1].str();
        if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0) continue;
        links.push_back({page, target});
      }
  return links;
}

TEST(DocsLinks, EveryRelativeLinkAndImageResolvesInsideTheRepository) {
  const std::vector<Link> links = relative_links();
  // The README links every page of docs/: far more than this, unless the parsing broke.
  ASSERT_GE(links.size(), 20u);
  for (const Link& link : links) {
    SCOPED_TRACE(link.page.string() + ": " + link.target);
    const std::string path = link.target.substr(0, link.target.find('#'));
    const fs::path file = path.empty() ? link.page : fs::weakly_canonical(link.page.parent_path() / path);
    const fs::path inside = file.lexically_relative(kRoot);
    EXPECT_FALSE(inside.empty() || *inside.begin() == "..") << "outside the repository: write it as plain text";
    EXPECT_TRUE(fs::exists(file)) << file << " does not exist";
  }
}

TEST(DocsLinks, EveryAnchorNamesAHeadingOfItsPage) {
  size_t anchors = 0;
  for (const Link& link : relative_links()) {
    const size_t hash = link.target.find('#');
    if (hash == std::string::npos) continue;
    SCOPED_TRACE(link.page.string() + ": " + link.target);
    const std::string path = link.target.substr(0, hash);
    const fs::path file = path.empty() ? link.page : link.page.parent_path() / path;
    if (file.extension() != ".md" || !fs::exists(file)) continue;  // the test above reports a missing file
    ++anchors;
    EXPECT_TRUE(heading_ids(file).count(link.target.substr(hash + 1))) << "no such heading in " << file;
  }
  EXPECT_GT(anchors, 0u);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
