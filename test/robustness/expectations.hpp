// Assertions shared by the robustness tests: a rejection must name its problem, a result must
// be internally consistent, and two results of the same frame must be identical.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include "ring_curvature/pipeline.hpp"

namespace ring_curvature
{
namespace test
{

inline std::string lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// True when `word` occurs in `text` as a whole token (so the field name "x" is not found in
/// "max_range"), case-insensitively; '_' counts as part of a token.
inline bool mentionsToken(const std::string& text, const std::string& word)
{
  const std::string t = lower(text), w = lower(word);
  auto is_word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t pos = t.find(w); pos != std::string::npos; pos = t.find(w, pos + 1))
  {
    const bool left = pos == 0 || !is_word(t[pos - 1]);
    const bool right = pos + w.size() >= t.size() || !is_word(t[pos + w.size()]);
    if (left && right)
      return true;
  }
  return false;
}

inline bool mentionsAny(const std::string& text, std::initializer_list<const char*> words)
{
  for (const char* w : words)
    if (lower(text).find(lower(w)) != std::string::npos)
      return true;
  return false;
}

/// Every array of a result has one entry per input point, labels are valid, the counts add up,
/// and every primitive's indices are in range and carry its id.
inline void expectConsistent(const FrameResult& r, std::size_t n)
{
  ASSERT_EQ(r.label.size(), n);
  ASSERT_EQ(r.curvature.size(), n);
  ASSERT_EQ(r.smoothness.size(), n);
  ASSERT_EQ(r.discontinuity.size(), n);
  ASSERT_EQ(r.primitive.size(), n);
  std::size_t counted = 0;
  for (std::size_t c : r.label_counts)
    counted += c;
  EXPECT_EQ(counted, n);
  for (std::size_t i = 0; i < n; ++i)
    ASSERT_LT(r.label[i], kNumLabels) << "point " << i;
  const auto& prims = r.primitives.primitives;
  for (std::size_t id = 0; id < prims.size(); ++id)
  {
    const PrimitiveInfo& p = prims[id];
    EXPECT_EQ(p.id, id);
    ASSERT_LE(static_cast<std::size_t>(p.first) + p.num_points, r.primitives.indices.size());
    for (std::uint32_t j = 0; j < p.num_points; ++j)
    {
      const std::uint32_t idx = r.primitives.indices[p.first + j];
      ASSERT_LT(idx, n);
      EXPECT_EQ(r.primitive[idx], static_cast<std::int32_t>(id));
      EXPECT_EQ(r.label[idx], static_cast<std::uint8_t>(p.label));
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    ASSERT_LT(r.primitive[i], static_cast<std::int32_t>(prims.size()));
}

/// A rejected frame leaves an empty result (pipeline.hpp's contract).
inline void expectEmpty(const FrameResult& r)
{
  EXPECT_TRUE(r.label.empty());
  EXPECT_TRUE(r.curvature.empty());
  EXPECT_TRUE(r.primitive.empty());
  EXPECT_TRUE(r.primitives.primitives.empty());
}

inline bool sameFloat(float a, float b)
{
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

inline void expectSameFloats(const std::vector<float>& a, const std::vector<float>& b,
                             const char* what)
{
  ASSERT_EQ(a.size(), b.size()) << what;
  std::size_t diffs = 0, first = a.size();
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!sameFloat(a[i], b[i]))
    {
      if (diffs++ == 0)
        first = i;
    }
  EXPECT_EQ(diffs, 0u) << what << ": first difference at point " << first;
}

/// Bit-for-bit the same output (NaN matches NaN): what a warm pipeline gives must equal what a
/// fresh one gives, whatever came before.
inline void expectSameResult(const FrameResult& a, const FrameResult& b)
{
  EXPECT_EQ(a.label, b.label);
  expectSameFloats(a.curvature, b.curvature, "curvature");
  expectSameFloats(a.smoothness, b.smoothness, "smoothness");
  expectSameFloats(a.discontinuity, b.discontinuity, "discontinuity");
  EXPECT_EQ(a.primitive, b.primitive);
  EXPECT_EQ(a.label_counts, b.label_counts);
  ASSERT_EQ(a.primitives.primitives.size(), b.primitives.primitives.size());
  EXPECT_EQ(a.primitives.indices, b.primitives.indices);
  for (std::size_t i = 0; i < a.primitives.primitives.size(); ++i)
  {
    const PrimitiveInfo &p = a.primitives.primitives[i], &q = b.primitives.primitives[i];
    EXPECT_EQ(p.label, q.label) << "primitive " << i;
    EXPECT_EQ(p.num_points, q.num_points) << "primitive " << i;
    EXPECT_TRUE(p.centroid == q.centroid) << "primitive " << i;
    EXPECT_TRUE(p.axis == q.axis) << "primitive " << i;
  }
}

}  // namespace test
}  // namespace ring_curvature
