#include "alloc_counter.hpp"

#include <atomic>
#include <cerrno>
#include <cstdlib>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__) || defined(__SANITIZE_MEMORY__)
#define RC_NO_MALLOC_INTERPOSITION 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define RC_NO_MALLOC_INTERPOSITION 1
#endif
#endif

namespace
{
std::atomic<bool> g_counting{false};
std::atomic<std::size_t> g_count{0};
inline void note()
{
  if (g_counting.load(std::memory_order_relaxed))
    g_count.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace

#ifndef RC_NO_MALLOC_INTERPOSITION
// glibc's real allocator under its exported internal names: calling these (rather than dlsym'ing
// the next malloc) cannot recurse, because dlsym itself allocates.
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);

void* malloc(std::size_t n) noexcept
{
  note();
  return __libc_malloc(n);
}
void* calloc(std::size_t a, std::size_t b) noexcept
{
  note();
  return __libc_calloc(a, b);
}
void* realloc(void* p, std::size_t n) noexcept
{
  note();
  return __libc_realloc(p, n);
}
void free(void* p) noexcept { __libc_free(p); }
void* memalign(std::size_t al, std::size_t n) noexcept
{
  note();
  return __libc_memalign(al, n);
}
void* aligned_alloc(std::size_t al, std::size_t n) noexcept
{
  note();
  return __libc_memalign(al, n);
}
int posix_memalign(void** out, std::size_t al, std::size_t n) noexcept
{
  note();
  void* p = __libc_memalign(al, n);
  if (p == nullptr)
    return ENOMEM;
  *out = p;
  return 0;
}
}
#endif

namespace ring_curvature
{
namespace test
{

bool allocCountingAvailable()
{
#ifdef RC_NO_MALLOC_INTERPOSITION
  return false;
#else
  return true;
#endif
}

void startCountingAllocations()
{
  g_count.store(0);
  g_counting.store(true);
}

std::size_t stopCountingAllocations()
{
  g_counting.store(false);
  return g_count.load();
}

}  // namespace test
}  // namespace ring_curvature
