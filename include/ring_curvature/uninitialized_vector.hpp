// A std::vector whose resize leaves new elements of trivial types unwritten: for per-frame
// arrays that are resized and then written entry by entry, where the zero fill of a plain
// vector's resize was pure overhead (a memset of the grid, 2 % of a frame under perf).
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace ring_curvature
{

/// std::allocator, except that value-initialization (`resize(n)`, `vector(n)`) becomes
/// default-initialization: no write for trivial types. Explicit values (`resize(n, v)`,
/// `assign`, `push_back`) are stored as usual.
template <class T>
struct DefaultInitAllocator : std::allocator<T>
{
  using std::allocator<T>::allocator;
  template <class U>
  struct rebind
  {
    using other = DefaultInitAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value)
  {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args)
  {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

/// A vector for arrays that are written in full after each resize.
template <class T>
using UninitializedVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace ring_curvature
