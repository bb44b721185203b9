#pragma once
// OMNISFM_ALSO_FOR_AVX2 before a function builds it also for AVX2, chosen when the processor has
// it (OpenCV too picks its filters' code by processor): for loops of a few instructions per pixel,
// where twice the lanes nearly halve them. The choice is made by the dynamic loader (an indirect
// function), which GNU/Linux's has; elsewhere the function is built once, for the baseline. On free
// functions only: Clang makes no variants of a member function (and leaves it undefined).

#if defined(__x86_64__) && defined(__ELF__) && defined(__GLIBC__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define OMNISFM_ALSO_FOR_AVX2 __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef OMNISFM_ALSO_FOR_AVX2
#define OMNISFM_ALSO_FOR_AVX2
#endif
