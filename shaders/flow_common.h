// GLSL only: the arithmetic the flow kernels share with their CPU twins, operation for
// operation, so that both backends agree to rounding (bit for bit on a device that honours
// `precise`; division and sqrt go through flow_div and flow_sqrt, which round correctly where the
// device's own are only faithful, as Vulkan allows and some GPUs' are):
//   flow_sample_field       = sample_field            (src/field/field_sampler.cpp)
//   flow_accumulate_face    = accumulate_face_gradient (src/flow/velocity.cpp)
// GLM's formulas are spelled out (mix, cross, length) because GLSL leaves the built-ins'
// operation order to the implementation; `precise` forbids fused multiply-adds, which the
// CPU build (x86-64 without -mfma) never forms either.
#ifndef FRACREF_FLOW_COMMON_H
#define FRACREF_FLOW_COMMON_H

// (p, e) with p + e = a·b exactly: Dekker's product on Veltkamp halves, from rounded +, −, ×
// alone (Vulkan requires those correctly rounded; fma() may be unfused, on lavapipe without
// FMA hardware for one).
vec2 flow_two_product(float a, float b) {
  precise float ca = 4097.0 * a, cb = 4097.0 * b;
  precise float ah = ca - (ca - a), bh = cb - (cb - b);
  precise float al = a - ah, bl = b - bh;
  precise float p = a * b;
  precise float e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
  return vec2(p, e);
}

// Exact comparisons for the rounding's last step. A positive normal float v is m·2^e with m its
// 24-bit integer significand (2^23 ≤ m < 2^24).
uint flow_significand(float v) { return (floatBitsToUint(v) & 0x7FFFFFu) | 0x800000u; }
int flow_exponent(float v) { return int((floatBitsToUint(v) >> 23) & 0xFFu) - 150; }
bool flow_normal(float v) { return v >= 1.17549435e-38 && v <= 3.40282347e38; }

// Whether m·2^k > (hi, lo) as 64-bit integers, for 0 ≤ k < 40 and m < 2^24.
bool flow_shifted_above(uint m, int k, uint hi, uint lo) {
  const uint shi = k >= 32 ? m << uint(k - 32) : (k == 0 ? 0u : m >> uint(32 - k));
  const uint slo = k >= 32 ? 0u : m << uint(k);
  return shi > hi || (shi == hi && slo > lo);
}

// Whether a > b·mid, mid the midpoint between q and the next float up (a, b, q positive normal):
// a = A·2^ea, b = B·2^eb, mid = (2Q + 1)·2^(eq − 1), so a > b·mid ⇔ A·2^(ea − eb − eq + 1) >
// B·(2Q + 1), under 2^49. Never equal: B·(2Q + 1) has more significant bits than A.
bool flow_quotient_above_mid(float a, float b, float q) {
  const int k = flow_exponent(a) - flow_exponent(b) - flow_exponent(q) + 1;
  if (k < 0) return false;
  if (k >= 40) return true;
  uint hi, lo;
  umulExtended(flow_significand(b), 2u * flow_significand(q) + 1u, hi, lo);
  return flow_shifted_above(flow_significand(a), k, hi, lo);
}

// Whether x > mid², mid the midpoint between s and the next float up (x, s positive normal):
// x = X·2^ex, mid² = (2S + 1)²·2^(2es − 2). Never equal, as above.
bool flow_root_above_mid(float x, float s) {
  const int k = flow_exponent(x) - 2 * flow_exponent(s) + 2;
  if (k < 0) return false;
  if (k >= 40) return true;
  uint hi, lo;
  const uint m = 2u * flow_significand(s) + 1u;
  umulExtended(m, m, hi, lo);
  return flow_shifted_above(flow_significand(x), k, hi, lo);
}

float flow_next_up(float v) { return uintBitsToFloat(floatBitsToUint(v) + 1u); }
float flow_next_down(float v) { return uintBitsToFloat(floatBitsToUint(v) - 1u); }

// a / b rounded to nearest from the device's faithful quotient q (Vulkan allows 2.5 ulp): with
// q·b = p + e, a − p is exact (Sterbenz: p is within a few ulps of a), so the residual
// r = (a − p) − e carries one rounding and q + r/b lands within an ulp of the correctly rounded
// quotient; the midpoint tests above (exact, in integers) then settle it, also where a/b lies a
// hair from a midpoint, which the residual alone cannot (ties cannot happen). Zero, huge,
// subnormal or non-finite q or b pass through (the split would overflow). flow_div_from takes q,
// so that tests can hand it a quotient a few ulps off.
float flow_div_from(float a, float b, float q) {
  if (q == 0.0 || !(max(abs(q), abs(b)) <= 1.0e30)) return q;
  const vec2 pe = flow_two_product(q, b);
  precise float r = (a - pe.x) - pe.y;
  precise float c = q + r / b;
  const float aa = abs(a), ab = abs(b);
  float m = abs(c);
  if (!flow_normal(aa) || !flow_normal(ab) || !flow_normal(m) || !flow_normal(flow_next_down(m))) return c;
  for (int i = 0; i < 2 && flow_quotient_above_mid(aa, ab, m); ++i) m = flow_next_up(m);
  for (int i = 0; i < 2 && !flow_quotient_above_mid(aa, ab, flow_next_down(m)); ++i) m = flow_next_down(m);
  return c < 0.0 ? -m : m;
}

float flow_div(float a, float b) {
  precise float q = a / b;
  return flow_div_from(a, b, q);
}

vec3 flow_div(vec3 a, float b) {
  return vec3(flow_div(a.x, b), flow_div(a.y, b), flow_div(a.z, b));
}

// sqrt(x) rounded to nearest from the device's faithful s, as flow_div: s + (x − s²) / 2s, then
// the exact midpoint tests (flow_sqrt_from takes s). The residual alone misses roots a hair from
// a midpoint: sqrt of the float just below a power of four lies 2^-27 ulp under one.
float flow_sqrt_from(float x, float s) {
  if (!(s > 0.0) || !(s <= 1.0e19)) return s;
  const vec2 pe = flow_two_product(s, s);
  precise float r = (x - pe.x) - pe.y;
  precise float c = s + r / (2.0 * s);
  if (!flow_normal(x) || !flow_normal(c) || !flow_normal(flow_next_down(c))) return c;
  for (int i = 0; i < 2 && flow_root_above_mid(x, c); ++i) c = flow_next_up(c);
  for (int i = 0; i < 2 && !flow_root_above_mid(x, flow_next_down(c)); ++i) c = flow_next_down(c);
  return c;
}

float flow_sqrt(float x) {
  precise float s = sqrt(x);
  return flow_sqrt_from(x, s);
}

// glm::mix(a, b, t) = a * (1 - t) + b * t.
vec4 flow_mix(vec4 a, vec4 b, float t) {
  precise vec4 r = a * (1.0 - t) + b * t;
  return r;
}

// glm::cross.
vec3 flow_cross(vec3 x, vec3 y) {
  precise vec3 r = vec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y);
  return r;
}

// Node (x, y, z) of a grid of `dims` stored x fastest in a vec4 texel buffer.
vec4 flow_node(samplerBuffer grid, uvec3 dims, uint x, uint y, uint z) {
  return texelFetch(grid, int(x + dims.x * (y + dims.y * z)));
}

// (ψ, ∇ψ) at p: g = (p − origin) / cell; i = clamp(floor(g), 0, n − 2); t = g − i (p clamped
// into the box), then trilinear interpolation of the four channels, x first, then y, then z.
vec4 flow_sample_field(samplerBuffer grid, uvec3 dims, vec4 origin_cell, vec3 p) {
  precise vec3 d = p - origin_cell.xyz;
  const vec3 g = flow_div(d, origin_cell.w);
  uvec3 i0;
  precise vec3 t;
  for (int a = 0; a < 3; ++a) {
    const float c = clamp(g[a], 0.0, float(dims[a] - 1u));
    i0[a] = min(uint(floor(c)), dims[a] - 2u);
    t[a] = c - float(i0[a]);
  }
  const uvec3 i1 = i0 + 1u;
  const vec4 c00 = flow_mix(flow_node(grid, dims, i0.x, i0.y, i0.z), flow_node(grid, dims, i1.x, i0.y, i0.z), t.x);
  const vec4 c10 = flow_mix(flow_node(grid, dims, i0.x, i1.y, i0.z), flow_node(grid, dims, i1.x, i1.y, i0.z), t.x);
  const vec4 c01 = flow_mix(flow_node(grid, dims, i0.x, i0.y, i1.z), flow_node(grid, dims, i1.x, i0.y, i1.z), t.x);
  const vec4 c11 = flow_mix(flow_node(grid, dims, i0.x, i1.y, i1.z), flow_node(grid, dims, i1.x, i1.y, i1.z), t.x);
  return flow_mix(flow_mix(c00, c10, t.y), flow_mix(c01, c11, t.y), t.z);
}

// One face (i, a, b) in its own orientation: grad += (A/3)∇ψ(x_i) + ½(n̂ × (x_b − x_a))ψ̄,
// mass += A/3; a degenerate face (zero or NaN area) adds nothing.
void flow_accumulate_face(vec3 xi, vec3 xa, vec3 xb, vec4 si, float psi_a, float psi_b, inout vec3 grad,
                          inout float mass) {
  const vec3 c = flow_cross(xa - xi, xb - xi);
  precise float squared = c.x * c.x + c.y * c.y + c.z * c.z;
  const float twice_area = flow_sqrt(squared);
  if (!(twice_area > 0.0)) return;
  const vec3 n = flow_div(c, twice_area);
  precise float third_area = twice_area * (1.0 / 6.0);
  precise float psi_mean = (si.x + psi_a + psi_b) * (1.0 / 3.0);
  precise vec3 term = third_area * si.yzw + 0.5 * psi_mean * flow_cross(n, xb - xa);
  precise vec3 sum = grad + term;
  precise float m = mass + third_area;
  grad = sum;
  mass = m;
}

// v = −grad / mass and the mass; zero when no face had an area.
vec3 flow_velocity(vec3 grad, float mass) {
  const vec3 v = flow_div(-grad, mass);
  return mass > 0.0 ? v : vec3(0.0);
}

#endif
