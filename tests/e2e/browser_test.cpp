// The headless-Chromium page check (browser.h) on small hand-written pages.
#include "tests/e2e/browser.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <chrono>
#include <fstream>

#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {
namespace fs = std::filesystem;

fs::path write_page(const fs::path& dir, const std::string& body, const std::string& name = "page.html") {
  std::ofstream(dir / name, std::ios::binary) << "<!doctype html>\n<html><head><meta charset=\"utf-8\">"
                                              << "<title>check</title></head>\n<body>\n"
                                              << body << "\n</body></html>\n";
  return dir / name;
}

void write_png(const fs::path& file, int width, int height) {
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out) << OIIO::geterror();
  const std::vector<unsigned char> pixels(static_cast<size_t>(width * height * 4), 200);
  ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(width, height, 4, OIIO::TypeDesc::UINT8))) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data())) << out->geterror();
  out->close();
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

TEST(Browser, GoodPageHasSectionsAndImagesAndNoErrors) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path dir = scratch("good");
  fs::create_directories(dir / "img");
  write_png(dir / "img" / "tiny.png", 2, 2);
  const fs::path page = write_page(dir, R"(<section class="pass" data-pass="a"><h2>a</h2></section>
<section class="pass" data-pass="b"><h2>b</h2><img src="img/tiny.png" alt="tiny"></section>
<section class="other" data-pass="not a pass">x</section>)");

  const auto start = std::chrono::steady_clock::now();
  const PageCheck check = check_page(page, dir / "browser");
  const auto took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("check_page_seconds", std::to_string(took));

  EXPECT_TRUE(check.console_errors.empty()) << joined(check.console_errors);
  EXPECT_EQ(check.title, "check");
  ASSERT_EQ(check.sections.size(), 2u);
  EXPECT_EQ(check.sections[0].pass, "a");
  EXPECT_EQ(check.sections[1].pass, "b");
  for (const PageSection& section : check.sections) {
    EXPECT_GT(section.width, 0) << section.pass;
    EXPECT_GT(section.height, 0) << section.pass;
  }
  ASSERT_EQ(check.images.size(), 1u);
  EXPECT_EQ(check.images[0].src, "img/tiny.png");
  EXPECT_EQ(check.images[0].natural_width, 2);
  EXPECT_EQ(check.images[0].natural_height, 2);
  EXPECT_TRUE(check.images[0].complete);
  // The page under test is left as it was, with nothing beside it.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 3) << "page.html, img, browser";
}

TEST(Browser, MissingImageIsAnError) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path dir = scratch("missing");
  const PageCheck check = check_page(
      write_page(dir, R"(<section class="pass" data-pass="a"><img src="missing.png"></section>)"), dir / "browser");
  ASSERT_EQ(check.console_errors.size(), 1u) << joined(check.console_errors);
  EXPECT_NE(check.console_errors[0].find("missing.png"), std::string::npos) << check.console_errors[0];
  EXPECT_NE(check.console_errors[0].find("ERR_FILE_NOT_FOUND"), std::string::npos) << check.console_errors[0];
  ASSERT_EQ(check.images.size(), 1u);
  EXPECT_EQ(check.images[0].src, "missing.png");
  EXPECT_EQ(check.images[0].natural_width, 0);
}

TEST(Browser, UncaughtExceptionsAreErrors) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path dir = scratch("throws");
  // Before any section exists, during load and after it: all of them count.
  const PageCheck check = check_page(write_page(dir, R"(<script>throw new Error("early boom");</script>
<section class="pass" data-pass="a">a</section>
<script>addEventListener("load", () => Promise.reject(new Error("late rejection")));</script>)"),
                                     dir / "browser");
  const std::string errors = joined(check.console_errors);
  ASSERT_EQ(check.console_errors.size(), 2u) << errors;
  EXPECT_NE(errors.find("Uncaught Error: early boom"), std::string::npos) << errors;
  EXPECT_NE(errors.find("late rejection"), std::string::npos) << errors;
  ASSERT_EQ(check.sections.size(), 1u);
}

TEST(Browser, ConsoleErrorIsAnErrorButLogAndWarnAreNot) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path dir = scratch("console");
  const PageCheck quiet = check_page(
      write_page(dir, R"(<script>console.log("hello"); console.info("info"); console.warn("warn");</script>)",
                 "log.html"),
      dir / "browser");
  EXPECT_TRUE(quiet.console_errors.empty()) << joined(quiet.console_errors);

  const PageCheck loud =
      check_page(write_page(dir, R"(<script>console.error("bad", 42);</script>)", "error.html"), dir / "browser");
  ASSERT_EQ(loud.console_errors.size(), 1u) << joined(loud.console_errors);
  EXPECT_NE(loud.console_errors[0].find("console.error: bad 42"), std::string::npos) << loud.console_errors[0];
}

TEST(Browser, PassNamesAreUnescaped) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path dir = scratch("escaped");
  const PageCheck check = check_page(
      write_page(dir, R"(<section class="pass" data-pass="&lt;script&gt;&quot;x&quot; &amp; 'y' – é">a</section>)"),
      dir / "browser");
  EXPECT_TRUE(check.console_errors.empty()) << joined(check.console_errors);
  ASSERT_EQ(check.sections.size(), 1u);
  EXPECT_EQ(check.sections[0].pass, "<script>\"x\" & 'y' – é");
}

TEST(Browser, MissingPageThrows) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path dir = scratch("absent");
  EXPECT_THROW(check_page(dir / "absent.html", dir / "browser"), std::runtime_error);
}

TEST(Browser, ScreenshotHasTheRequestedSize) {
  NIGHTCAP_REQUIRE_CHROMIUM();
  const fs::path dir = scratch("screenshot");
  // Taller than the window: the screenshot is of the window, not the whole page.
  const fs::path page = write_page(dir, R"(<section class="pass" data-pass="a" style="height: 2000px">a</section>)");
  screenshot_page(page, dir / "shot.png", 320, 200, dir / "browser");
  auto in = OIIO::ImageInput::open((dir / "shot.png").string());
  ASSERT_TRUE(in) << OIIO::geterror();
  EXPECT_EQ(in->spec().width, 320);
  EXPECT_EQ(in->spec().height, 200);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
