// Helpers for the CPU-shaped primitive kernels.
#ifndef SPLATCL_PRIMITIVES_CPU_H
#define SPLATCL_PRIMITIVES_CPU_H

#define SPLATCL_CONCAT_(a, b) a##b
#define SPLATCL_CONCAT(a, b) SPLATCL_CONCAT_(a, b)

// Streaming (non-temporal) store where the compiler offers one (clang, as in PoCL): the CPU writes
// whole cache lines without reading them first, which cuts the memory traffic of scatters whose
// output is not read again soon. Elsewhere a plain store.
#if defined(__clang__) && defined(__has_builtin)
#if __has_builtin(__builtin_nontemporal_store)
#define STREAM_STORE(value, pointer) __builtin_nontemporal_store((value), (pointer))
#endif
#endif
#ifndef STREAM_STORE
#define STREAM_STORE(value, pointer) (*(pointer) = (value))
#endif
// Streaming stores are weakly ordered: a work-item fences them before it ends (on x86 only SFENCE
// does; PoCL compiles mem_fence to a compiler barrier).
#if defined(__clang__) && defined(__has_builtin) && defined(__x86_64__)
#if __has_builtin(__builtin_ia32_sfence)
#define STREAM_STORES_DONE() __builtin_ia32_sfence()
#endif
#endif
#ifndef STREAM_STORES_DONE
#define STREAM_STORES_DONE() mem_fence(CLK_GLOBAL_MEM_FENCE)
#endif

#endif  // SPLATCL_PRIMITIVES_CPU_H
