#pragma once
// Internal: an AVX2 (x86-64-v3) clone of each hot kernel, chosen at load time, so one binary
// is fast on modern CPUs and still runs on any x86-64.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(DEEPSEA_NO_CLONES)
#define DEEPSEA_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
// AVX2 without FMA: loops whose products and sums must round as the generic clone's do.
#define DEEPSEA_CLONES_NO_FMA __attribute__((target_clones("avx2", "default")))
#else
#define DEEPSEA_CLONES
#define DEEPSEA_CLONES_NO_FMA
#endif
