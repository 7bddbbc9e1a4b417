// K2: velocity[i] = (v_i, M_i), gathering over the faces incident to vertex i through the
// vertex→faces CSR, in CSR order (the twin of vertex_velocities_cpu; see src/flow/velocity.hpp
// for the formula). Reads K1's samples after a barrier in the same submit.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "layout.h"
#include "flow_common.h"

layout(local_size_x = FRACREF_WORKGROUP) in;

layout(binding = 0) uniform samplerBuffer positions;   // xyz used
layout(binding = 1) uniform usamplerBuffer faces;      // xyz = vertex ids in the face's orientation
layout(binding = 2) uniform usamplerBuffer vf_offsets; // vertices + 1 entries
layout(binding = 3) uniform usamplerBuffer vf_faces;
layout(binding = 4) uniform samplerBuffer samples;     // K1's output
layout(std430, binding = 5) writeonly buffer Velocity { vec4 velocity[]; };
layout(std140, binding = 6) uniform Params { FlowParams p; };

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= p.counts.x) return;
  const vec3 xi = texelFetch(positions, int(i)).xyz;
  const vec4 si = texelFetch(samples, int(i));
  vec3 grad = vec3(0.0);
  float mass = 0.0;
  const uint end = texelFetch(vf_offsets, int(i) + 1).x;
  for (uint k = texelFetch(vf_offsets, int(i)).x; k < end; ++k) {
    const uvec3 f = texelFetch(faces, int(texelFetch(vf_faces, int(k)).x)).xyz;
    // The corners after i in the face's orientation.
    uvec2 ab = f.yz;
    if (f.y == i) ab = f.zx;
    else if (f.z == i) ab = f.xy;
    flow_accumulate_face(xi, texelFetch(positions, int(ab.x)).xyz, texelFetch(positions, int(ab.y)).xyz, si,
                         texelFetch(samples, int(ab.x)).x, texelFetch(samples, int(ab.y)).x, grad, mass);
  }
  velocity[i] = mass > 0.0 ? vec4(flow_velocity(grad, mass), mass) : vec4(0.0);
}
