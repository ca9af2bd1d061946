#pragma once
// LOOM_TARGET_CLONES: compile a hot function twice, for x86-64-v3 (AVX2, FMA) and
// for the baseline, and pick one at load time (GCC's target_clones). Empty under
// ThreadSanitizer, which instruments the ifunc resolver the clones need while the
// dynamic loader calls it before TSan's runtime is up (a crash at start), and under
// clang (the fuzz build), whose clones of a member function template leave their
// resolvers undefined at link time (clang 14).

#if defined(__SANITIZE_THREAD__) || defined(__clang__)
#define LOOM_TARGET_CLONES
#else
#define LOOM_TARGET_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#endif
