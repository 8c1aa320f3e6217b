// The guard in front of OpenEXR when it reads an image blob.
#pragma once

#include <filesystem>
#include <vector>

namespace nightcap {

// The data window size each part of a blob must have, in order.
struct ExpectedPart {
  int width, rows;
};

// OpenEXR 3.1 trusts the headers it reads: it allocates an attribute's stated size before
// reading it (2 GiB for one damaged string size), reads fixed-size values and channel lists
// without comparing what it read with the stated size (so where it reads next can be anywhere),
// and sizes its tables from the data window and chunk count. So before OpenEXR opens a blob, its
// headers are walked here and must hold what write_image_blob writes and nothing else: a
// scanline file with the expected number of parts, only the attributes nightcap writes, each of
// its type and of that type's size, inside the file, with each part's data window of the
// expected size and a chunk count no larger than its rows. Then OpenEXR reads the same attributes
// at the same places and allocates only what the blob's raw size bounds.
// Throws CaptureError naming `file` and the first problem.
void check_exr_headers(const std::filesystem::path& file, const std::vector<ExpectedPart>& parts);

}  // namespace nightcap
