#pragma once
// Runtime CPU dispatch for the integer loops the compiler vectorises (Canny's per-pixel tests,
// the box filter, the peak scan). The build targets baseline x86-64 (SSE2) so the binaries
// run on any PC; with this attribute GCC also emits an AVX2 copy of the function and the
// loader picks it when the CPU has AVX2, twice the lanes. Integer arithmetic only, so both
// copies give identical results. Elsewhere (ARM, other compilers) it expands to nothing.

// Not under ThreadSanitizer: the clones' ifunc resolvers run while the program is loaded, before
// TSan's runtime is set up, and crash there (GCC 12).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(SB_NO_CPU_DISPATCH) && !defined(__SANITIZE_THREAD__)
#define SB_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define SB_AVX2_CLONE
#endif

// Hand-written AVX2 kernels (intrinsics, where the compiler cannot vectorise a loop by itself):
// a function marked SB_TARGET_AVX2 may use AVX2 instructions and is called only when
// cpu_has_avx2(); its plain twin runs otherwise and must give the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(SB_NO_CPU_DISPATCH)
#define SB_HAVE_AVX2_KERNELS 1
#define SB_TARGET_AVX2 __attribute__((target("avx2")))
namespace stereoball::ball_detector {
/// Whether this CPU runs AVX2 code (asked once).
inline bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
}  // namespace stereoball::ball_detector
#else
#define SB_HAVE_AVX2_KERNELS 0
#endif
