#include "captures/exr_zip.h"

#include <libdeflate.h>

#include <cstring>
#include <memory>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace nightcap {
namespace {

struct FreeDecompressor {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

// Each thread decoding chunks keeps its decompressor and the buffer it inflates into.
libdeflate_decompressor* thread_decompressor() {
  thread_local const std::unique_ptr<libdeflate_decompressor, FreeDecompressor> decompressor(
      libdeflate_alloc_decompressor());
  return decompressor.get();
}

std::vector<uint8_t>& thread_filtered() {
  thread_local std::vector<uint8_t> filtered;
  return filtered;
}

// filtered[i] += filtered[i - 1] - 128 for i >= 1: a running sum of bytes.
void undo_differences(uint8_t* bytes, size_t n) {
  size_t i = 1;
#if defined(__SSE2__)
  // A vector's running sum in four shifted adds, then the sum so far (the last byte of the
  // vector before, in every lane; kept in a register, as a load of the byte just stored would
  // wait for the store) added to every lane.
  const __m128i bias = _mm_set1_epi8(-128);
  __m128i sum = _mm_set1_epi8(char(bytes[0]));
  for (; i + 16 <= n; i += 16) {
    __m128i x = _mm_add_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + i)), bias);
    x = _mm_add_epi8(x, _mm_slli_si128(x, 1));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 2));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 4));
    x = _mm_add_epi8(x, _mm_slli_si128(x, 8));
    x = _mm_add_epi8(x, sum);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(bytes + i), x);
    // Byte 15 into every lane: doubled into 16-bit lanes, then the last of those, then its pair.
    sum = _mm_shuffle_epi32(_mm_shufflehi_epi16(_mm_unpackhi_epi8(x, x), 0xff), 0xff);
  }
#endif
  for (; i < n; ++i) bytes[i] = uint8_t(bytes[i - 1] + bytes[i] - 128);
}

// out[2k] = first[k], out[2k + 1] = second[k].
void interleave_halves(const uint8_t* first, const uint8_t* second, uint8_t* out, size_t n) {
  const size_t pairs = n / 2;
  size_t k = 0;
#if defined(__SSE2__)
  for (; k + 16 <= pairs; k += 16) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(first + k));
    const __m128i y = _mm_loadu_si128(reinterpret_cast<const __m128i*>(second + k));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * k), _mm_unpacklo_epi8(x, y));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 2 * k + 16), _mm_unpackhi_epi8(x, y));
  }
#endif
  for (; k < pairs; ++k) {
    out[2 * k] = first[k];
    out[2 * k + 1] = second[k];
  }
  if (n % 2) out[n - 1] = first[pairs];
}

}  // namespace

void unfilter_zip(uint8_t* filtered, uint8_t* out, size_t n) {
  if (n == 0) return;
  undo_differences(filtered, n);
  interleave_halves(filtered, filtered + (n + 1) / 2, out, n);
}

exr_result_t inflate_zip_chunk(exr_decode_pipeline_t* pipeline) {
  const size_t packed = pipeline->chunk.packed_size, unpacked = pipeline->chunk.unpacked_size;
  // OpenEXR stores a chunk as it is when compressing would not make it smaller.
  if (packed == unpacked) {
    if (pipeline->unpacked_buffer != pipeline->packed_buffer)
      std::memcpy(pipeline->unpacked_buffer, pipeline->packed_buffer, unpacked);
    return EXR_ERR_SUCCESS;
  }
  std::vector<uint8_t>& filtered = thread_filtered();
  if (filtered.size() < unpacked) filtered.resize(unpacked);
  size_t inflated = 0;
  if (libdeflate_zlib_decompress(thread_decompressor(), pipeline->packed_buffer, packed, filtered.data(), unpacked,
                                 &inflated) != LIBDEFLATE_SUCCESS ||
      inflated != unpacked)
    return EXR_ERR_CORRUPT_CHUNK;
  unfilter_zip(filtered.data(), static_cast<uint8_t*>(pipeline->unpacked_buffer), unpacked);
  return EXR_ERR_SUCCESS;
}

}  // namespace nightcap
