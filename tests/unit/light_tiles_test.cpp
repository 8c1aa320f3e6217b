// The tile bookkeeping the sun's moving shadow maps share (passes/shadow/light_tiles.h), on
// small maps whose answers can be counted by hand: a 16-texel map in 4×4 tiles of 4 texels.
#include <gtest/gtest.h>

#include "passes/shadow/light_tiles.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr uint32_t kTiles = 4, kResolution = 16;

uint64_t bit(uint32_t tx, uint32_t ty) { return uint64_t(1) << (ty * kTiles + tx); }

TEST(LightTiles, AMoveUncoversTheEdgeTilesItLeavesAndKeepsTheRest) {
  const TiledMap map{{0.0, 0.0}, 1.0, kResolution, kTiles};
  // Texel t now covers t + (3, 0) before: the last column of tiles takes 3 texels from outside.
  const TilesAfterMove right = tiles_after_move(map.all(), {3, 0}, kTiles, kResolution);
  EXPECT_EQ(right.stale, 0u);
  EXPECT_EQ(right.uncovered, bit(3, 0) | bit(3, 1) | bit(3, 2) | bit(3, 3));
  // Up and to the left by one texel: the first row and the first column.
  const TilesAfterMove corner = tiles_after_move(map.all(), {-1, -1}, kTiles, kResolution);
  EXPECT_EQ(corner.stale, 0u);
  EXPECT_EQ(corner.uncovered, bit(0, 0) | bit(1, 0) | bit(2, 0) | bit(3, 0) | bit(0, 1) | bit(0, 2) | bit(0, 3));
  // No move keeps every tile as it was; a tile that was not complete stays stale.
  const TilesAfterMove still = tiles_after_move(map.all() & ~bit(2, 2), {0, 0}, kTiles, kResolution);
  EXPECT_EQ(still.stale, bit(2, 2));
  EXPECT_EQ(still.uncovered, 0u);
  // Moved by a texel, the tiles that take texels from the incomplete one are stale too.
  const TilesAfterMove spread = tiles_after_move(map.all() & ~bit(2, 2), {1, 1}, kTiles, kResolution);
  EXPECT_EQ(spread.stale, bit(1, 1) | bit(2, 1) | bit(1, 2) | bit(2, 2));
  // A move past the whole map uncovers every tile.
  EXPECT_EQ(tiles_after_move(map.all(), {40, 0}, kTiles, kResolution).uncovered, map.all());
}

TEST(LightTiles, UncoveredStripsHoldEveryUncoveredTexelOnce) {
  for (const glm::ivec2 shift : {glm::ivec2(3, 0), glm::ivec2(0, -2), glm::ivec2(-1, -1), glm::ivec2(5, 7),
                                 glm::ivec2(-20, 1), glm::ivec2(0, 0)}) {
    SCOPED_TRACE(testing::Message() << "shift " << shift.x << ", " << shift.y);
    const UncoveredStrips strips = uncovered_strips(kResolution, shift);
    for (int y = 0; y < int(kResolution); ++y)
      for (int x = 0; x < int(kResolution); ++x) {
        const glm::ivec2 source = glm::ivec2(x, y) + shift;
        const bool uncovered =
            source.x < 0 || source.y < 0 || source.x >= int(kResolution) || source.y >= int(kResolution);
        auto in = [&](const MapTexels& r) { return x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1; };
        EXPECT_EQ(int(in(strips.columns)) + int(in(strips.rows)), int(uncovered)) << "texel " << x << ", " << y;
      }
  }
}

TEST(LightTiles, TheTilesARectangleMeetsIncludeTheTexelAroundEachTile) {
  const TiledMap map{{-8.0, -8.0}, 1.0, kResolution, kTiles};  // tiles of 4 m from (-8, -8)
  EXPECT_EQ(map.meeting({{-7.0, -7.0}, {-6.0, -6.0}}), bit(0, 0));
  // A texel from tile (1, 0)'s edge: within the texel the tile is grown by, so both tiles.
  EXPECT_EQ(map.meeting({{-4.5, -7.0}, {-4.4, -6.0}}), bit(0, 0) | bit(1, 0));
  EXPECT_EQ(map.meeting({{-100.0, -100.0}, {100.0, 100.0}}), map.all());
  EXPECT_EQ(map.meeting({{20.0, 20.0}, {21.0, 21.0}}), 0u);
  const TiledMap whole{{0.0, 0.0}, 1.0, 64, 8};
  EXPECT_EQ(whole.all(), ~uint64_t(0));
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
