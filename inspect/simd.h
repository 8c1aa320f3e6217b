// Loops that the diff runs over every value of an image, written for SIMD. GCC and Clang compile
// arithmetic on these vector types to SIMD instructions, which they would not do for the plain
// loops at -O2; where the CPU has AVX2 (chosen when the program loads) a function marked
// NIGHTCAP_AVX2_CLONE runs a clone compiled for it, and one marked NIGHTCAP_SIMD_CLONES also has an
// AVX-512 clone (wider registers, and twice as many of them). No clone fuses multiply-adds (the
// build's -ffp-contract=off): every clone does the same operations in the same order, so their
// results are the same bits.
//
// Values of these types are passed only inside one function: a helper taking or returning one
// would have a different calling convention in each clone.
#pragma once

#include <cstdint>

namespace nightcap::simd {

using Floats16 = float __attribute__((vector_size(64)));
using Floats8 = float __attribute__((vector_size(32)));
using Floats4 = float __attribute__((vector_size(16)));
using Doubles4 = double __attribute__((vector_size(32)));
using Words8 = uint32_t __attribute__((vector_size(32)));
using Halves8 = uint16_t __attribute__((vector_size(16)));

}  // namespace nightcap::simd

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define NIGHTCAP_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#define NIGHTCAP_SIMD_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define NIGHTCAP_AVX2_CLONE
#define NIGHTCAP_SIMD_CLONES
#endif
