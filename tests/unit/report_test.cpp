// The report's building blocks: escaping of names from captures, numbers as the page prints them,
// and thumbnails shrunk by averaging light, not codes.
#include <gtest/gtest.h>

#include "reports/html.h"
#include "reports/thumbnails.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

TEST(ReportHtml, EscapesMarkupQuotesAndBrokenText) {
  EXPECT_EQ(escape_markup("<script>alert(\"x\")</script>"), "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt;");
  EXPECT_EQ(escape_markup("a & b's ../c"), "a &amp; b&#39;s ../c");
  EXPECT_EQ(escape_markup("&lt;"), "&amp;lt;");  // already escaped text stays what it said
  EXPECT_EQ(escape_markup("tab\tline\nnul\x01."), "tab\tline\nnul\xef\xbf\xbd.");
  // Valid UTF-8 passes; a stray continuation byte, an overlong form and a truncated sequence
  // become U+FFFD each.
  EXPECT_EQ(escape_markup("×°→"), "×°→");
  EXPECT_EQ(escape_markup("a\x80z"), "a\xef\xbf\xbdz");
  EXPECT_EQ(escape_markup("\xc0\xaf"), "\xef\xbf\xbd\xef\xbf\xbd");
  EXPECT_EQ(escape_markup("\xe2\x86"), "\xef\xbf\xbd\xef\xbf\xbd");
}

TEST(ReportHtml, NumbersAreFixedWithSignificantDigitsAndNoTrailingZeros) {
  EXPECT_EQ(format_number(1362.4, 3), "1362");
  EXPECT_EQ(format_number(20.44, 3), "20.4");
  EXPECT_EQ(format_number(0.02513, 3), "0.0251");
  EXPECT_EQ(format_number(1.0, 6), "1");
  EXPECT_EQ(format_number(0.0), "0");
  EXPECT_EQ(format_number(2.5e-7, 3), "2.5e-07");
  EXPECT_EQ(format_number(INFINITY), "∞");
  EXPECT_EQ(format_number(NAN), "NaN");
}

Rgba8Image picture(uint32_t w, uint32_t h, std::vector<uint8_t> rgb_codes) {
  Rgba8Image image{w, h, {}};
  for (size_t i = 0; i < rgb_codes.size(); ++i)
    image.pixels.insert(image.pixels.end(), {rgb_codes[i], rgb_codes[i], rgb_codes[i], 255});
  return image;
}

TEST(Thumbnail, AveragesLightForSrgbPicturesAndCodesForData) {
  // Black and white side by side, shrunk to one pixel: half the light is sRGB code 188
  // (0.5 linear encodes to 0.7354); as plain data, the mean code 127.5 rounds to 128.
  const Rgba8Image edge = picture(2, 1, {0, 255});
  const Rgba8Image light = shrink(edge, 1, true);
  ASSERT_EQ(light.width, 1u);
  ASSERT_EQ(light.height, 1u);
  EXPECT_EQ(light.pixels[0], 188);
  EXPECT_EQ(light.pixels[3], 255);
  EXPECT_EQ(shrink(edge, 1, false).pixels[0], 128);
}

TEST(Thumbnail, KeepsTheAspectAndLeavesSmallPicturesAlone) {
  const Rgba8Image wide = shrink(picture(1280, 720, std::vector<uint8_t>(1280 * 720, 7)), 256, true);
  EXPECT_EQ(wide.width, 256u);
  EXPECT_EQ(wide.height, 144u);
  for (size_t i = 0; i < wide.pixels.size(); i += 4) ASSERT_EQ(wide.pixels[i], 7);  // flat stays flat
  const Rgba8Image tall = shrink(picture(3, 1000, std::vector<uint8_t>(3000, 0)), 100, false);
  EXPECT_EQ(tall.height, 100u);
  EXPECT_EQ(tall.width, 1u);  // never 0 wide
  const Rgba8Image small = picture(2, 2, {1, 2, 3, 4});
  EXPECT_EQ(shrink(small, 256, true).pixels, small.pixels);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
