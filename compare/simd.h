// Loops that the diff runs over every value of an image, written for SIMD. GCC and Clang compile
// arithmetic on these vector types to SIMD instructions, which they would not do for the plain
// loops at -O2. Such a loop is written once, as an always-inlined body, and simd::Compiled stamps
// out one function per path: generic (any x86-64: SSE2), AVX2, and AVX-512 (wider registers, and
// twice as many of them) for a loop that gains from it. The program calls `dispatch`, which runs
// the widest path the CPU has; a test calls each path through `on` and holds it to the generic
// one's bits.
//
// The paths' results are the same bits because each does the same IEEE operations in the same
// order: the build's -ffp-contract=off keeps GCC from fusing a multiply and an add into one FMA
// (one rounding instead of two), which it does otherwise on the AVX-512 path (AVX-512F has FMA
// instructions; GCC's "avx2" target has none, nor has the generic one): without it
// SimdPaths.WeightedSum and SimdPaths.ClampedHuntLab fail. Where the inputs hold NaNs, a path may
// return another NaN: x86 returns the first of two NaN operands, and the compiler may order a
// commutative operation's operands differently on each path (FLIP rejects such inputs).
//
// Values of these vector types are passed only inside one body: a helper taking or returning one
// by value would have a different calling convention on each path (GCC's -Wpsabi).
#pragma once

#include <cstdint>
#include <vector>

namespace nightcap::simd {

using Floats16 = float __attribute__((vector_size(64)));
using Floats8 = float __attribute__((vector_size(32)));
using Floats4 = float __attribute__((vector_size(16)));
using Doubles4 = double __attribute__((vector_size(32)));
using Words8 = uint32_t __attribute__((vector_size(32)));
using Halves8 = uint16_t __attribute__((vector_size(16)));

// Ordered from narrowest to widest.
enum class Path : uint8_t { generic, avx2, avx512 };

const char* path_name(Path path);
bool cpu_has(Path path);
// The paths this CPU runs, generic first.
std::vector<Path> supported_paths();
// The widest of them, found once.
Path widest_path();

#if defined(__x86_64__) && defined(__GNUC__)
#define NIGHTCAP_SIMD_TARGET(name) __attribute__((target(name)))
#else
#define NIGHTCAP_SIMD_TARGET(name)
#endif

// `body` compiled once per path up to `widest`; a loop that does not gain from AVX-512 runs its
// AVX2 function on the AVX-512 path. `body` must be [[gnu::always_inline]], so that each path's
// function holds a copy of it compiled for that path's instructions.
template <auto body, Path widest = Path::avx512>
struct Compiled;

template <typename Result, typename... Args, Result (*body)(Args...), Path widest>
struct Compiled<body, widest> {
  using Function = Result (*)(Args...);

  static Result generic(Args... args) { return body(static_cast<Args&&>(args)...); }
  NIGHTCAP_SIMD_TARGET("avx2") static Result avx2(Args... args) { return body(static_cast<Args&&>(args)...); }
  NIGHTCAP_SIMD_TARGET("avx512f") static Result avx512(Args... args) { return body(static_cast<Args&&>(args)...); }

  // The function of `path`, which the caller has checked the CPU has.
  static Function on(Path path) {
    if constexpr (widest >= Path::avx512)
      if (path >= Path::avx512) return avx512;
    if constexpr (widest >= Path::avx2)
      if (path >= Path::avx2) return avx2;
    return generic;
  }

  // The widest path's function, chosen at the first call (a function-local static, so that a call
  // from any static initialiser finds it chosen).
  static Result dispatch(Args... args) {
    static const Function chosen = on(widest_path());
    return chosen(static_cast<Args&&>(args)...);
  }
};

}  // namespace nightcap::simd
