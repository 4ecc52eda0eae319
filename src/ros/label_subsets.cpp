// The landmark clouds (~planes, ~edges): the input records of the points of one or two labels,
// in the input's own layout.

#include "ring_curvature/ros/outputs.hpp"

#include "label_subsets.hpp"
#include "record_copy.hpp"
#include "ring_curvature/ros/recycle.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace ring_curvature
{

namespace
{

// The top bit of every byte of `x` that is zero, and no other bit: exact per byte, as no sum
// carries from one byte into the next (the classic (x - 1...1) & ~x test's borrow may also mark
// a byte above a zero one).
inline std::uint64_t zeroBytes(std::uint64_t x)
{
  constexpr std::uint64_t lows = 0x7f7f7f7f7f7f7f7full, highs = 0x8080808080808080ull;
  return ~(((x & lows) + lows) | x) & highs;
}

// Number of labels equal to a or b. Counted in blocks with a byte counter: the compiler then
// compares and adds 16 labels per instruction, where a size_t counter made it widen every byte.
std::size_t countLabels(const std::uint8_t* label, std::size_t n, std::uint8_t a, std::uint8_t b)
{
  std::size_t count = 0;
  for (std::size_t first = 0; first < n; first += 255)
  {
    const std::size_t last = std::min(n, first + 255);
    std::uint8_t c = 0;
    for (std::size_t i = first; i < last; ++i)
      c = static_cast<std::uint8_t>(c + ((label[i] == a) | (label[i] == b)));
    count += c;
  }
  return count;
}

// Copies the records of the points labelled `a` or `b`, in order, to `dst` .. `end` (sized for
// exactly those). Dense subsets (the planes are most of a frame) copy every record and advance
// only past kept ones, without a branch per point to mispredict; sparse ones (edges) test first.
template <class Copy>
void copySubset(const sensor_msgs::PointCloud2& in, const std::uint8_t* label, std::uint8_t a, std::uint8_t b,
                bool dense, std::uint8_t* dst, std::uint8_t* const end, Copy copy)
{
  // (a cloud without columns has no points, however many rows it declares)
  const std::uint32_t width = in.width, height = width > 0 ? in.height : 0;
  const std::size_t point_step = in.point_step, row_step = in.row_step;
  const std::uint8_t* const data = in.data.data();
  for (std::uint32_t row = 0; row < height; ++row, label += width)
  {
    const std::uint8_t* const src = data + row * row_step;
    if (dense)
    {
      for (std::uint32_t col = 0; col < width; ++col)
      {
        if (dst == end)  // every kept point copied (and no room for another record)
          return;
        copy(dst, src + col * point_step);
        dst += ((label[col] == a) | (label[col] == b)) ? point_step : 0;
      }
    }
    else
    {
      const auto keep = [&](std::uint32_t col) {
        if (label[col] == a || label[col] == b)
        {
          copy(dst, src + col * point_step);
          dst += point_step;
        }
      };
      // Eight labels at a time, skipped whole when none of them is a or b (most words).
      std::uint32_t col = 0;
      for (; col + 8 <= width; col += 8)
      {
        std::uint64_t w;
        std::memcpy(&w, label + col, 8);
        // One bit per kept label, visited lowest first, which is column order (little-endian):
        // a branch per kept point, where testing each of the eight labels of a word with one
        // mispredicted around every kept point (edges are scattered).
        constexpr std::uint64_t ones = 0x0101010101010101ull;
        std::uint64_t hits = zeroBytes(w ^ (ones * a)) | zeroBytes(w ^ (ones * b));
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
        for (; hits != 0; hits &= hits - 1)
        {
          const auto k = static_cast<std::uint32_t>(__builtin_ctzll(hits)) / 8;
          copy(dst, src + (col + k) * point_step);
          dst += point_step;
        }
#else
        if (hits != 0)
          for (std::uint32_t k = col; k < col + 8; ++k)
            keep(k);
#endif
      }
      for (; col < width; ++col)
        keep(col);
    }
  }
}

}  // namespace

namespace detail
{

// Declared in label_subsets.hpp: shared with the one-pass labelled and plane clouds.
std::size_t subsetLayout(const sensor_msgs::PointCloud2& input, const FrameResult& result, std::uint8_t a,
                         std::uint8_t b, sensor_msgs::PointCloud2& cloud)
{
  sensor_msgs::PointCloud2* const out = &cloud;
  out->header = input.header;
  out->fields = input.fields;
  out->is_bigendian = false;
  // Only valid (finite, in range) returns get a label other than None.
  out->is_dense = true;
  out->point_step = input.point_step;
  out->height = 1;
  const std::size_t count = countLabels(result.label.data(), result.label.size(), a, b);
  out->width = static_cast<std::uint32_t>(count);
  out->row_step = out->width * out->point_step;
  out->data.resize(count * out->point_step);  // every record is copied in by the caller
  return count;
}

}  // namespace detail

sensor_msgs::PointCloud2Ptr makeLabelSubset(const sensor_msgs::PointCloud2& input, const FrameResult& result,
                                            Label a, Label b, sensor_msgs::PointCloud2Ptr reuse)
{
  auto out = recycled(std::move(reuse));
  const auto la = static_cast<std::uint8_t>(a), lb = static_cast<std::uint8_t>(b);
  const std::uint8_t* const label = result.label.data();
  const std::size_t count = detail::subsetLayout(input, result, la, lb, *out);
  if (count > 0)
  {
    std::uint8_t* const dst = out->data.data();
    const bool dense = 4 * count > result.label.size();
    detail::withCopier(input.point_step, [&](auto copy) {
      copySubset(input, label, la, lb, dense, dst, dst + count * input.point_step, copy);
    });
  }
  return out;
}

}  // namespace ring_curvature
