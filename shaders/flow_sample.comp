// K1: samples[i] = (ψ, ∇ψ)(x_i), one trilinear fetch of the FieldGrid4 per vertex (the twin of
// sample_vertices_cpu). One invocation per vertex, dispatched indirectly (see FlowParams).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "layout.h"
#include "flow_common.h"

layout(local_size_x = FRACREF_WORKGROUP) in;

layout(binding = 0) uniform samplerBuffer field;      // vec4 (ψ, ∇ψ) per grid node, x fastest
layout(binding = 1) uniform samplerBuffer positions;  // xyz used
layout(std430, binding = 2) writeonly buffer Samples { vec4 samples[]; };
layout(std140, binding = 3) uniform Params { FlowParams p; };

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= p.counts.x) return;
  samples[i] = flow_sample_field(field, p.field_dims.xyz, p.field_origin, texelFetch(positions, int(i)).xyz);
}
