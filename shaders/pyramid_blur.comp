// One decimating 1D Gaussian pass of the pyramid (see BlurParams in layout.h): one invocation
// per output node; dispatched as ceil(nx*ny / FRACREF_WORKGROUP) x nz workgroups (output dims). Arithmetic in the order of src/field/pyramid.hpp: acc = 0, then for
// k = -r..r ascending acc += w[k+r] * src[clamp(2c+k)]; `precise` forbids fused multiply-adds
// so the result matches the CPU twin bit for bit where that one does not fuse either.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "layout.h"

layout(local_size_x = FRACREF_WORKGROUP) in;

layout(binding = 0) uniform samplerBuffer src;  // uniform texel buffer: fast gathers on lavapipe
layout(std430, binding = 1) writeonly buffer Dst { float dst[]; };
layout(std140, binding = 2) uniform Weights { BlurWeights weights; };
layout(push_constant) uniform Push { BlurParams p; };

void main() {
  const uvec3 d = p.dst_dims.xyz;
  // One dispatch row of workgroups per z plane: a single division per invocation (integer
  // division is scalar on lavapipe, so a flat index's second division costs), and idle lanes only
  // in the last workgroup of each plane (a 3D dispatch idles most lanes on narrow grids).
  const uint j = gl_GlobalInvocationID.x;
  if (j >= d.x * d.y) return;
  const uint y = j / d.x;
  const uvec3 g = uvec3(j - y * d.x, y, gl_GlobalInvocationID.y);
  const uint i = j + d.x * d.y * g.z;
  const uint axis = p.src_dims.w;
  const int r = int(p.dst_dims.w);
  const ivec3 s = ivec3(p.src_dims.xyz);
  ivec3 c = ivec3(g);
  c[axis] *= 2;
  const int stride = axis == 0u ? 1 : (axis == 1u ? s.x : s.x * s.y);
  const int line = c.x + s.x * (c.y + s.y * c.z) - c[axis] * stride;  // the node at coordinate 0
  const int last = s[axis] - 1;
  precise float acc = 0.0;
  for (int k = -r; k <= r; ++k) {
    const int j = k + r;
    acc += weights.w[j >> 2][j & 3] * texelFetch(src, line + clamp(c[axis] + k, 0, last) * stride).r;
  }
  dst[i] = acc;
}
