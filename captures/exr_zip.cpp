#include "captures/exr_zip.h"

#include <libdeflate.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace nightcap {
namespace {

struct FreeDecompressor {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};
struct FreeCompressor {
  void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
};

// Each thread decoding chunks keeps its decompressor and the buffer it inflates into.
libdeflate_decompressor* thread_decompressor() {
  thread_local const std::unique_ptr<libdeflate_decompressor, FreeDecompressor> decompressor(
      libdeflate_alloc_decompressor());
  return decompressor.get();
}

// Each thread encoding chunks keeps a compressor per level.
libdeflate_compressor* thread_compressor(int level) {
  constexpr int kLevels = 12;  // libdeflate's 1 ... 12
  thread_local std::unique_ptr<libdeflate_compressor, FreeCompressor> compressors[kLevels];
  auto& compressor = compressors[std::clamp(level, 1, kLevels) - 1];
  if (!compressor) compressor.reset(libdeflate_alloc_compressor(std::clamp(level, 1, kLevels)));
  if (!compressor) throw std::bad_alloc();
  return compressor.get();
}

std::vector<uint8_t>& thread_filtered() {
  thread_local std::vector<uint8_t> filtered;
  return filtered;
}

// first[k] = bytes[2k], second[k] = bytes[2k + 1]: interleave_halves undone.
void split_halves(const uint8_t* bytes, uint8_t* first, uint8_t* second, size_t n) {
  const size_t pairs = n / 2;
  size_t k = 0;
#if defined(__SSE2__)
  const __m128i low = _mm_set1_epi16(0x00ff);
  for (; k + 16 <= pairs; k += 16) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 2 * k));
    const __m128i y = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 2 * k + 16));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(first + k),
                     _mm_packus_epi16(_mm_and_si128(x, low), _mm_and_si128(y, low)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(second + k),
                     _mm_packus_epi16(_mm_srli_epi16(x, 8), _mm_srli_epi16(y, 8)));
  }
#endif
  for (; k < pairs; ++k) {
    first[k] = bytes[2 * k];
    second[k] = bytes[2 * k + 1];
  }
  if (n % 2) first[pairs] = bytes[n - 1];
}

// bytes[i] = bytes[i] - bytes[i - 1] + 128 for i >= 1, each from the bytes as they were.
void take_differences(uint8_t* bytes, size_t n) {
  if (n < 2) return;
  size_t i = 1;
  uint8_t previous = bytes[0];
#if defined(__SSE2__)
  const __m128i bias = _mm_set1_epi8(-128);
  // The vector before, as it was: its last byte comes first in the next vector's predecessors.
  __m128i before = _mm_slli_si128(_mm_cvtsi32_si128(bytes[0]), 15);
  for (; i + 16 <= n; i += 16) {
    const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + i));
    const __m128i predecessors = _mm_or_si128(_mm_slli_si128(x, 1), _mm_srli_si128(before, 15));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(bytes + i), _mm_add_epi8(_mm_sub_epi8(x, predecessors), bias));
    before = x;
  }
  previous = uint8_t(_mm_cvtsi128_si32(_mm_srli_si128(before, 15)));
#endif
  for (; i < n; ++i) {
    const uint8_t current = bytes[i];
    bytes[i] = uint8_t(current - previous + 128);
    previous = current;
  }
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

void filter_zip(const uint8_t* bytes, uint8_t* out, size_t n) {
  split_halves(bytes, out, out + (n + 1) / 2, n);
  take_differences(out, n);
}

void deflate_zip_chunk(std::span<const uint8_t> samples, int level, std::vector<uint8_t>& out) {
  if (samples.empty()) return;
  std::vector<uint8_t>& filtered = thread_filtered();
  if (filtered.size() < samples.size()) filtered.resize(samples.size());
  filter_zip(samples.data(), filtered.data(), samples.size());
  const size_t start = out.size();
  // Room for the samples as they are: a deflated chunk is kept only when it is smaller.
  out.resize(start + samples.size());
  const size_t deflated = libdeflate_zlib_compress(thread_compressor(level), filtered.data(), samples.size(),
                                                   out.data() + start, samples.size() - 1);
  if (deflated == 0) {
    std::copy(samples.begin(), samples.end(), out.begin() + std::ptrdiff_t(start));
    return;
  }
  out.resize(start + deflated);
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
