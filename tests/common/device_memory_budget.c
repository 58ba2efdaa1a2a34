/*
 * An LD_PRELOAD library that gives lavapipe a small GPU memory, so that tests
 * can make the driver itself run out of memory (tests/gpu_memory.rs).
 *
 * Assumption, checked by the tests that use it (they fail if it stops
 * holding): lavapipe (Mesa 22.3) backs each vkAllocateMemory with one
 * page-aligned posix_memalign call, and wgpu allocates device memory in
 * blocks of at least 4 MiB (MemoryHints::MemoryUsage). Other page-aligned
 * allocations in the process are small (Mesa makes a few of 192 bytes).
 *
 * KDRAY_TEST_DEVICE_MEMORY_BYTES is the budget: page-aligned allocations of
 * 1 MiB or more count against it, in total over the process's life (frees are
 * not tracked: one render allocates and keeps), and the first that would go
 * beyond it fails with ENOMEM, as a real allocation does when memory is
 * exhausted. lavapipe then returns VK_ERROR_OUT_OF_DEVICE_MEMORY to wgpu.
 * Without the variable every call is passed through unchanged.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stddef.h>
#include <stdlib.h>

typedef int (*posix_memalign_fn)(void **, size_t, size_t);

static size_t counted_bytes;

int posix_memalign(void **out, size_t alignment, size_t size) {
    static posix_memalign_fn real;
    if (!real) {
        real = (posix_memalign_fn)dlsym(RTLD_NEXT, "posix_memalign");
        if (!real) {
            return ENOMEM;
        }
    }
    const char *budget_text = getenv("KDRAY_TEST_DEVICE_MEMORY_BYTES");
    if (budget_text && alignment >= 4096 && size >= (1u << 20)) {
        size_t budget = (size_t)strtoull(budget_text, NULL, 10);
        size_t before = __atomic_load_n(&counted_bytes, __ATOMIC_SEQ_CST);
        do {
            if (size > budget || before > budget - size) {
                return ENOMEM;
            }
        } while (!__atomic_compare_exchange_n(&counted_bytes, &before, before + size, 0,
                                              __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST));
    }
    return real(out, alignment, size);
}
