// K3: out[k] = (v_s, ψ(s)) for candidate sample k over its own neighbourhood, the triangles
// (s, a, b) of its fan (the twin of sample_velocities_cpu). One invocation per sample.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "layout.h"
#include "flow_common.h"

layout(local_size_x = FRACREF_WORKGROUP) in;

layout(binding = 0) uniform samplerBuffer field;        // vec4 (ψ, ∇ψ) per grid node, x fastest
layout(binding = 1) uniform samplerBuffer positions;    // of the surface's vertices, xyz used
layout(binding = 2) uniform samplerBuffer samples;      // (ψ, ∇ψ) of the surface's vertices
layout(binding = 3) uniform samplerBuffer points;       // sample positions, xyz used
layout(binding = 4) uniform usamplerBuffer fan_offsets; // samples + 1 entries
layout(binding = 5) uniform usamplerBuffer fan_pairs;   // (a, b): triangle (s, a, b)
layout(std430, binding = 6) writeonly buffer Out { vec4 result[]; };
layout(std140, binding = 7) uniform Params { FlowParams p; };

void main() {
  const uint k = gl_GlobalInvocationID.x;
  if (k >= p.counts.y) return;
  const vec3 xs = texelFetch(points, int(k)).xyz;
  const vec4 ss = flow_sample_field(field, p.field_dims.xyz, p.field_origin, xs);
  vec3 grad = vec3(0.0);
  float mass = 0.0;
  const uint end = texelFetch(fan_offsets, int(k) + 1).x;
  for (uint q = texelFetch(fan_offsets, int(k)).x; q < end; ++q) {
    const uvec2 ab = texelFetch(fan_pairs, int(q)).xy;
    flow_accumulate_face(xs, texelFetch(positions, int(ab.x)).xyz, texelFetch(positions, int(ab.y)).xyz, ss,
                         texelFetch(samples, int(ab.x)).x, texelFetch(samples, int(ab.y)).x, grad, mass);
  }
  result[k] = vec4(flow_velocity(grad, mass), ss.x);
}
