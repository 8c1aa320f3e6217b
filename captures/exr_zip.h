// OpenEXR's ZIP and ZIPS chunks inflated with libdeflate instead of OpenEXR's zlib. Reading a
// capture is mostly inflating its blobs: on a 1280x720 RGBA16F blob OpenEXR 3.1 took 17.4 ms,
// 5 of them zlib's inflate, 4.4 its byte-at-a-time undoing of the ZIP filter. libdeflate
// inflates the same chunks about twice as fast, and the filter undone 16 bytes at a time costs
// 0.8 ms: 6.3 ms in all, bit for bit the same pixels.
#pragma once

#include <openexr.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace nightcap {

// A decompress_fn for OpenEXR's core decode pipeline of a ZIP or ZIPS part: inflates
// pipeline->packed_buffer into pipeline->unpacked_buffer and undoes the filter. Fails with
// EXR_ERR_CORRUPT_CHUNK when the chunk is not a zlib stream of exactly the unpacked size.
exr_result_t inflate_zip_chunk(exr_decode_pipeline_t* pipeline);

// The ZIP filter undone: `filtered` (n bytes, overwritten) held the differences of successive
// bytes, offset by 128, of the first halves of every sample followed by their second halves;
// `out` gets the samples' bytes back in order.
void unfilter_zip(uint8_t* filtered, uint8_t* out, size_t n);

// The ZIP filter: what unfilter_zip undoes. `out` gets n bytes.
void filter_zip(const uint8_t* bytes, uint8_t* out, size_t n);

// Appends to `out` a ZIP or ZIPS chunk of `samples` (its lines' samples, channel by channel) as
// OpenEXR stores it: filtered and deflated by libdeflate at zlib `level`, or the samples as they
// are where that would be no smaller.
void deflate_zip_chunk(std::span<const uint8_t> samples, int level, std::vector<uint8_t>& out);

}  // namespace nightcap
