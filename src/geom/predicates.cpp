#include "geom/predicates.hpp"

#include <atomic>
#include <cfloat>
#include <cmath>

// Error-free transformations and the error bounds below assume IEEE double arithmetic with
// round-to-nearest and no extended intermediate precision.
#if defined(__FAST_MATH__)
#error "fracref geom: exact predicates and CCD error bounds must not be built with -ffast-math"
#endif
static_assert(FLT_EVAL_METHOD == 0, "fracref geom: needs double evaluation without extended precision");

namespace fracref {
namespace {

// Shewchuk's epsilon: half an ulp of 1, the relative rounding error of one operation.
constexpr double kEpsilon = 0x1p-53;
// Error bounds of the filters, from Shewchuk (1997), "Adaptive Precision Floating-Point
// Arithmetic and Fast Robust Geometric Predicates", section 4.
constexpr double kCcwErrBoundA = (3.0 + 16.0 * kEpsilon) * kEpsilon;
constexpr double kO3dErrBoundA = (7.0 + 56.0 * kEpsilon) * kEpsilon;

std::atomic<unsigned long long> g_orient2d_exact{0};
std::atomic<unsigned long long> g_orient3d_exact{0};

// Error-free transformations: a op b == x + y exactly (round-to-nearest, no overflow).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x;
  const double av = x + bv;
  y = (a - av) + (bv - b);
}

// The fused multiply-add gives the exact rounding error of a product in one operation.
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// An expansion is a sum of doubles, nonoverlapping, sorted by increasing magnitude, zeros
// removed (Shewchuk's representation). Its sign is the sign of its last component.

// h = e * b. Shewchuk's scale_expansion_zeroelim. h needs room for 2*elen components.
int scale_expansion(int elen, const double* e, double b, double* h) {
  if (elen == 0) return 0;
  int hn = 0;
  double q, hh;
  two_product(e[0], b, q, hh);
  if (hh != 0.0) h[hn++] = hh;
  for (int i = 1; i < elen; ++i) {
    double p1, p0, sum;
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, sum, hh);
    if (hh != 0.0) h[hn++] = hh;
    two_sum(p1, sum, q, hh);  // |p1| >= |sum| would allow fast_two_sum; two_sum is always exact
    if (hh != 0.0) h[hn++] = hh;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

// h = e + f. Shewchuk's fast_expansion_sum_zeroelim: merge the components by magnitude, then
// sweep with two_sum. Exact and nonoverlapping under round-to-nearest-even (his Theorem 13).
// h needs room for elen + flen components.
int expansion_sum(int elen, const double* e, int flen, const double* f, double* h) {
  int ei = 0, fi = 0, hn = 0;
  auto next = [&]() {
    if (fi >= flen || (ei < elen && std::fabs(e[ei]) < std::fabs(f[fi]))) return e[ei++];
    return f[fi++];
  };
  if (elen + flen == 0) return 0;
  double q = next();
  while (ei < elen || fi < flen) {
    double sum, hh;
    two_sum(q, next(), sum, hh);
    if (hh != 0.0) h[hn++] = hh;
    q = sum;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

int expansion_sign(int n, const double* e) {
  if (n == 0) return 0;
  return e[n - 1] > 0.0 ? 1 : (e[n - 1] < 0.0 ? -1 : 0);
}

// A two-component expansion from a difference of two doubles.
struct Two {
  double c[2];
  int n;
};

Two exact_diff(double a, double b) {
  Two t{};
  double x, y;
  two_diff(a, b, x, y);
  t.n = 0;
  if (y != 0.0) t.c[t.n++] = y;
  if (x != 0.0) t.c[t.n++] = x;
  return t;
}

// h = e * f for a general expansion e and a two-component f. h needs room for 4*elen.
int mul_two(int elen, const double* e, const Two& f, double* h) {
  double p0[32], p1[32];
  if (f.n == 0) return 0;
  const int n0 = scale_expansion(elen, e, f.c[0], p0);
  if (f.n == 1) {
    for (int i = 0; i < n0; ++i) h[i] = p0[i];
    return n0;
  }
  const int n1 = scale_expansion(elen, e, f.c[1], p1);
  return expansion_sum(n0, p0, n1, p1, h);
}

// h = a*b - c*d for two-component a, b, c, d. h needs room for 16 components.
int exact_minor(const Two& a, const Two& b, const Two& c, const Two& d, double* h) {
  double ab[8], cd[8];
  const int nab = mul_two(a.n, a.c, b, ab);
  const int ncd = mul_two(c.n, c.c, d, cd);
  for (int i = 0; i < ncd; ++i) cd[i] = -cd[i];
  return expansion_sum(nab, ab, ncd, cd, h);
}

int orient2d_exact(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  g_orient2d_exact.fetch_add(1, std::memory_order_relaxed);
  const Two acx = exact_diff(a.x, c.x), acy = exact_diff(a.y, c.y);
  const Two bcx = exact_diff(b.x, c.x), bcy = exact_diff(b.y, c.y);
  double det[16];
  const int n = exact_minor(acx, bcy, acy, bcx, det);
  return expansion_sign(n, det);
}

int orient3d_exact(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  g_orient3d_exact.fetch_add(1, std::memory_order_relaxed);
  const Two adx = exact_diff(a.x, d.x), ady = exact_diff(a.y, d.y), adz = exact_diff(a.z, d.z);
  const Two bdx = exact_diff(b.x, d.x), bdy = exact_diff(b.y, d.y), bdz = exact_diff(b.z, d.z);
  const Two cdx = exact_diff(c.x, d.x), cdy = exact_diff(c.y, d.y), cdz = exact_diff(c.z, d.z);
  // det = adz*(bdx*cdy - cdx*bdy) + bdz*(cdx*ady - adx*cdy) + cdz*(adx*bdy - bdx*ady)
  double m[16], t1[64], t2[64], t3[64], s12[128], det[192];
  int nm = exact_minor(bdx, cdy, cdx, bdy, m);
  const int n1 = mul_two(nm, m, adz, t1);
  nm = exact_minor(cdx, ady, adx, cdy, m);
  const int n2 = mul_two(nm, m, bdz, t2);
  nm = exact_minor(adx, bdy, bdx, ady, m);
  const int n3 = mul_two(nm, m, cdz, t3);
  const int n12 = expansion_sum(n1, t1, n2, t2, s12);
  const int n = expansion_sum(n12, s12, n3, t3, det);
  return expansion_sign(n, det);
}

int sign_of(double x) { return x > 0.0 ? 1 : (x < 0.0 ? -1 : 0); }

}  // namespace

int orient2d(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  const double detleft = (a.x - c.x) * (b.y - c.y);
  const double detright = (a.y - c.y) * (b.x - c.x);
  const double det = detleft - detright;
  const double errbound = kCcwErrBoundA * (std::fabs(detleft) + std::fabs(detright));
  if (det > errbound || -det > errbound) return sign_of(det);
  return orient2d_exact(a, b, c);
}

int orient2d_projected(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int drop_axis) {
  const int i = drop_axis == 0 ? 1 : 0;
  const int j = drop_axis == 2 ? 1 : 2;
  return orient2d({a[i], a[j]}, {b[i], b[j]}, {c[i], c[j]});
}

int orient3d(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
  const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
  const double adz = a.z - d.z, bdz = b.z - d.z, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  const double errbound = kO3dErrBoundA * permanent;
  if (det > errbound || -det > errbound) return sign_of(det);
  return orient3d_exact(a, b, c, d);
}

PredicateStats predicate_stats() {
  return {g_orient2d_exact.load(std::memory_order_relaxed), g_orient3d_exact.load(std::memory_order_relaxed)};
}

}  // namespace fracref
