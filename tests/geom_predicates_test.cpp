// Exact orientation predicates against an independent exact reference: 64-bit integers on
// small grids, and a small big-integer evaluation for arbitrary doubles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "geom/predicates.hpp"

namespace {

using fracref::orient2d;
using fracref::orient3d;
using glm::dvec2;
using glm::dvec3;

// Signed big integer, magnitude in base 2^32, little-endian. Just what a determinant needs.
struct Big {
  bool neg = false;
  std::vector<std::uint32_t> mag;

  void trim() {
    while (!mag.empty() && mag.back() == 0) mag.pop_back();
    if (mag.empty()) neg = false;
  }
  int sign() const { return mag.empty() ? 0 : (neg ? -1 : 1); }
};

int cmp_mag(const Big& a, const Big& b) {
  if (a.mag.size() != b.mag.size()) return a.mag.size() < b.mag.size() ? -1 : 1;
  for (std::size_t i = a.mag.size(); i-- > 0;)
    if (a.mag[i] != b.mag[i]) return a.mag[i] < b.mag[i] ? -1 : 1;
  return 0;
}

std::vector<std::uint32_t> add_mag(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  std::vector<std::uint32_t> r(std::max(a.size(), b.size()) + 1, 0);
  std::uint64_t carry = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const std::uint64_t s = carry + (i < a.size() ? a[i] : 0) + (i < b.size() ? b[i] : 0);
    r[i] = static_cast<std::uint32_t>(s);
    carry = s >> 32;
  }
  return r;
}

// |a| - |b| for |a| >= |b|.
std::vector<std::uint32_t> sub_mag(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
  std::vector<std::uint32_t> r(a.size(), 0);
  std::int64_t borrow = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    std::int64_t d = static_cast<std::int64_t>(a[i]) - (i < b.size() ? b[i] : 0) - borrow;
    borrow = d < 0 ? 1 : 0;
    if (d < 0) d += (std::int64_t(1) << 32);
    r[i] = static_cast<std::uint32_t>(d);
  }
  return r;
}

Big add(const Big& a, const Big& b) {
  Big r;
  if (a.neg == b.neg) {
    r.mag = add_mag(a.mag, b.mag);
    r.neg = a.neg;
  } else if (cmp_mag(a, b) >= 0) {
    r.mag = sub_mag(a.mag, b.mag);
    r.neg = a.neg;
  } else {
    r.mag = sub_mag(b.mag, a.mag);
    r.neg = b.neg;
  }
  r.trim();
  return r;
}

Big neg(Big a) {
  a.neg = !a.neg;
  a.trim();
  return a;
}

Big sub(const Big& a, const Big& b) { return add(a, neg(b)); }

Big mul(const Big& a, const Big& b) {
  Big r;
  r.mag.assign(a.mag.size() + b.mag.size() + 1, 0);
  for (std::size_t i = 0; i < a.mag.size(); ++i) {
    std::uint64_t carry = 0;
    for (std::size_t j = 0; j < b.mag.size(); ++j) {
      const std::uint64_t cur = r.mag[i + j] + std::uint64_t(a.mag[i]) * b.mag[j] + carry;
      r.mag[i + j] = static_cast<std::uint32_t>(cur);
      carry = cur >> 32;
    }
    std::size_t k = i + b.mag.size();
    while (carry) {
      const std::uint64_t cur = r.mag[k] + carry;
      r.mag[k++] = static_cast<std::uint32_t>(cur);
      carry = cur >> 32;
    }
  }
  r.neg = a.neg != b.neg;
  r.trim();
  return r;
}

// The exponent of the last mantissa bit of x (x = m * 2^e with integer m).
int low_exponent(double x) { return x == 0.0 ? 1 << 20 : std::ilogb(x) - 52; }

// x / 2^e as an exact big integer. \pre x is an integer multiple of 2^e.
Big scaled(double x, int e) {
  Big r;
  if (x == 0.0) return r;
  r.neg = x < 0;
  int ex = 0;
  const double frac = std::frexp(std::fabs(x), &ex);  // |x| = frac * 2^ex, frac in [0.5, 1)
  std::uint64_t m = static_cast<std::uint64_t>(std::ldexp(frac, 53));
  int shift = ex - 53 - e;  // |x| = m * 2^(shift + e)
  EXPECT_GE(shift, 0);
  r.mag = {static_cast<std::uint32_t>(m), static_cast<std::uint32_t>(m >> 32)};
  for (; shift >= 32; shift -= 32) r.mag.insert(r.mag.begin(), 0u);
  if (shift > 0) {
    std::uint32_t carry = 0;
    for (auto& w : r.mag) {
      const std::uint32_t next = w >> (32 - shift);
      w = (w << shift) | carry;
      carry = next;
    }
    if (carry) r.mag.push_back(carry);
  }
  r.trim();
  return r;
}

int reference_orient3d(const dvec3& a, const dvec3& b, const dvec3& c, const dvec3& d) {
  int e = 1 << 20;
  for (const dvec3* p : {&a, &b, &c, &d})
    for (int k = 0; k < 3; ++k) e = std::min(e, low_exponent((*p)[k]));
  auto big = [&](const dvec3& p, int k) { return scaled(p[k], e); };
  Big ad[3], bd[3], cd[3];
  for (int k = 0; k < 3; ++k) {
    ad[k] = sub(big(a, k), big(d, k));
    bd[k] = sub(big(b, k), big(d, k));
    cd[k] = sub(big(c, k), big(d, k));
  }
  const Big m1 = sub(mul(bd[0], cd[1]), mul(cd[0], bd[1]));
  const Big m2 = sub(mul(cd[0], ad[1]), mul(ad[0], cd[1]));
  const Big m3 = sub(mul(ad[0], bd[1]), mul(bd[0], ad[1]));
  return add(add(mul(ad[2], m1), mul(bd[2], m2)), mul(cd[2], m3)).sign();
}

int reference_orient2d(const dvec2& a, const dvec2& b, const dvec2& c) {
  int e = 1 << 20;
  for (const dvec2* p : {&a, &b, &c})
    for (int k = 0; k < 2; ++k) e = std::min(e, low_exponent((*p)[k]));
  const Big acx = sub(scaled(a.x, e), scaled(c.x, e)), acy = sub(scaled(a.y, e), scaled(c.y, e));
  const Big bcx = sub(scaled(b.x, e), scaled(c.x, e)), bcy = sub(scaled(b.y, e), scaled(c.y, e));
  return sub(mul(acx, bcy), mul(acy, bcx)).sign();
}

int sign64(std::int64_t x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

double ulps(double x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, INFINITY);
  for (; k < 0; ++k) x = std::nextafter(x, -INFINITY);
  return x;
}

TEST(GeomPredicates, SignConventions) {
  EXPECT_EQ(orient2d({0, 0}, {1, 0}, {0, 1}), 1);
  EXPECT_EQ(orient2d({0, 0}, {0, 1}, {1, 0}), -1);
  EXPECT_EQ(orient2d({0, 0}, {1, 1}, {2, 2}), 0);
  // d below the plane of a counterclockwise (seen from +z) triangle: positive.
  EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}), 1);
  EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), -1);
  EXPECT_EQ(orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 7, 0}), 0);
  EXPECT_EQ(fracref::orient2d_projected({0, 0, 9}, {1, 0, 3}, {0, 1, 4}, 2), 1);
  EXPECT_EQ(fracref::orient2d_projected({9, 0, 0}, {3, 1, 0}, {4, 0, 1}, 0), 1);
}

TEST(GeomPredicates, SmallIntegerGridsMatchIntegerDeterminants) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> coord(-3, 3);
  int zeros3 = 0, zeros2 = 0;
  for (int it = 0; it < 200000; ++it) {
    std::int64_t p[4][3];
    for (auto& q : p)
      for (auto& x : q) x = coord(rng);
    const dvec3 a(p[0][0], p[0][1], p[0][2]), b(p[1][0], p[1][1], p[1][2]);
    const dvec3 c(p[2][0], p[2][1], p[2][2]), d(p[3][0], p[3][1], p[3][2]);
    std::int64_t m[3][3];
    for (int k = 0; k < 3; ++k) {
      m[0][k] = p[0][k] - p[3][k];
      m[1][k] = p[1][k] - p[3][k];
      m[2][k] = p[2][k] - p[3][k];
    }
    const std::int64_t det = m[0][2] * (m[1][0] * m[2][1] - m[2][0] * m[1][1]) +
                             m[1][2] * (m[2][0] * m[0][1] - m[0][0] * m[2][1]) +
                             m[2][2] * (m[0][0] * m[1][1] - m[1][0] * m[0][1]);
    ASSERT_EQ(orient3d(a, b, c, d), sign64(det)) << it;
    zeros3 += det == 0;
    const std::int64_t det2 = (p[0][0] - p[2][0]) * (p[1][1] - p[2][1]) - (p[0][1] - p[2][1]) * (p[1][0] - p[2][0]);
    ASSERT_EQ(orient2d({a.x, a.y}, {b.x, b.y}, {c.x, c.y}), sign64(det2)) << it;
    zeros2 += det2 == 0;
  }
  EXPECT_GT(zeros3, 1000);  // the grid is small enough to be full of degeneracies
  EXPECT_GT(zeros2, 1000);
}

// Kettner et al.'s classroom example: points within a few ulps of the line y = x, where naive
// evaluation gets the sign wrong. Exact sign: orient2d(p, (12,12), (24,24)) = sign(12(py - px)).
TEST(GeomPredicates, Orient2dNearTheDiagonalLine) {
  const auto before = fracref::predicate_stats().orient2d_exact;
  const double ulp = std::ldexp(1.0, -53);
  int naive_wrong = 0;
  for (int i = 0; i < 256; ++i)
    for (int j = 0; j < 256; ++j) {
      const dvec2 p(0.5 + i * ulp, 0.5 + j * ulp), q(12, 12), r(24, 24);
      const int expected = j > i ? 1 : (j < i ? -1 : 0);
      ASSERT_EQ(orient2d(p, q, r), expected) << i << "," << j;
      const double naive = (p.x - r.x) * (q.y - r.y) - (p.y - r.y) * (q.x - r.x);
      naive_wrong += (naive > 0 ? 1 : (naive < 0 ? -1 : 0)) != expected;
    }
  EXPECT_GT(naive_wrong, 0);  // the input is hard for plain floating point
  EXPECT_GT(fracref::predicate_stats().orient2d_exact, before);
}

// Points within a few ulps of the plane x = z.
TEST(GeomPredicates, Orient3dNearAPlane) {
  const double ulp = std::ldexp(1.0, -53);
  const dvec3 a(12, 0, 12), b(24, 5, 24), c(7, 19, 7);  // on x = z, normal along (1, 0, -1)
  const int side = orient3d(a, b, c, {1, 0, 0});
  ASSERT_NE(side, 0);
  for (int i = 0; i < 64; ++i)
    for (int k = 0; k < 64; ++k) {
      const dvec3 d(0.5 + i * ulp, 0.25, 0.5 + k * ulp);
      const int expected = i > k ? side : (i < k ? -side : 0);
      ASSERT_EQ(orient3d(a, b, c, d), expected) << i << "," << k;
    }
}

TEST(GeomPredicates, ExactlyCoplanarLargeIntegersAndOneUlpAway) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> coord(-(std::int64_t(1) << 50), std::int64_t(1) << 50);
  const auto before = fracref::predicate_stats().orient3d_exact;
  for (int it = 0; it < 2000; ++it) {
    dvec3 a, b, c;
    for (int k = 0; k < 3; ++k) {
      a[k] = static_cast<double>(coord(rng));
      b[k] = static_cast<double>(coord(rng));
      c[k] = static_cast<double>(coord(rng));
    }
    const dvec3 d = a + (b - c);  // exact: all values below 2^53
    ASSERT_EQ(orient3d(a, b, c, d), 0) << it;
    for (int k = 0; k < 3; ++k)
      for (int step : {-1, 1}) {
        dvec3 e = d;
        e[k] = ulps(e[k], step);
        ASSERT_EQ(orient3d(a, b, c, e), reference_orient3d(a, b, c, e)) << it;
      }
  }
  EXPECT_GT(fracref::predicate_stats().orient3d_exact, before);
}

TEST(GeomPredicates, RandomNearlyCoplanarPerturbationsMatchBigIntegerReference) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), weight(-0.5, 1.5);
  int nonzero = 0, zero = 0;
  for (int it = 0; it < 3000; ++it) {
    const dvec3 a(unit(rng), unit(rng), unit(rng)), b(unit(rng), unit(rng), unit(rng)), c(unit(rng), unit(rng), unit(rng));
    const double s = weight(rng), t = weight(rng);
    const dvec3 base = a + s * (b - a) + t * (c - a);
    for (int k = -2; k <= 2; ++k) {
      const dvec3 d(ulps(base.x, k), ulps(base.y, -k), base.z);
      const int expected = reference_orient3d(a, b, c, d);
      ASSERT_EQ(orient3d(a, b, c, d), expected) << it << " " << k;
      ASSERT_EQ(orient3d(d, a, b, c), -expected);  // odd permutation flips the sign
      expected == 0 ? ++zero : ++nonzero;
    }
    const dvec2 p(a.x, a.y), q(b.x, b.y), r = p + s * (q - p);
    for (int k = -2; k <= 2; ++k) {
      const dvec2 rr(ulps(r.x, k), r.y);
      ASSERT_EQ(orient2d(p, q, rr), reference_orient2d(p, q, rr)) << it << " " << k;
    }
  }
  EXPECT_GT(nonzero, 1000);
}

TEST(GeomPredicates, TinyAndHugeScalesKeepTheSign) {
  // Scaling by a power of two is exact, so the sign must not change.
  const dvec3 a(0.1, 0.2, 0.3), b(0.7, -0.1, 0.2), c(-0.3, 0.5, 0.9);
  const dvec3 d = a + 0.25 * (b - a) + 0.5 * (c - a);
  const int s = orient3d(a, b, c, d);
  EXPECT_EQ(s, reference_orient3d(a, b, c, d));
  for (int e : {-40, -20, 20, 40}) {
    const double f = std::ldexp(1.0, e);
    EXPECT_EQ(orient3d(f * a, f * b, f * c, f * d), s) << e;
  }
}

}  // namespace
