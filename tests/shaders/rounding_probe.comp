// Test-only (tests/vk_rounding_test.cpp): case k = (a, b, q, s) with q a quotient a/b and s a
// square root of |a|, each a few ulps off as a faithful device may round them;
// out[k] = (flow_div_from(a, b, q), flow_sqrt_from(|a|, s)), which must be the correctly
// rounded a/b and sqrt(|a|).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "flow_common.h"

layout(local_size_x = 64) in;

layout(binding = 0) uniform samplerBuffer cases;
layout(std430, binding = 1) writeonly buffer Out { vec2 result[]; };

void main() {
  const uint k = gl_GlobalInvocationID.x;
  const vec4 c = texelFetch(cases, int(k));
  result[k] = vec2(flow_div_from(c.x, c.y, c.z), flow_sqrt_from(abs(c.x), c.w));
}
