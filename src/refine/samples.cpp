#include "refine/samples.hpp"

#include <algorithm>

#include <cmath>

#include "util/parallel.hpp"

namespace fracref {
namespace {

constexpr float kMinWeight = 0.15f;

// lowbias32 (Chris Wellons): a strong 32-bit integer finalizer; the same in GLSL.
std::uint32_t mix32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

void add_edge_fan(const FractureSurface& s, std::uint32_t edge, SampleSet& out) {
  glm::uvec2 e = s.edges[edge];
  for (std::uint32_t k = s.ef_offsets[edge]; k < s.ef_offsets[edge + 1]; ++k) {
    glm::uvec3 c(s.faces[s.ef_faces[k]]);
    while (!((c.x == e.x && c.y == e.y) || (c.x == e.y && c.y == e.x))) c = glm::uvec3(c.y, c.z, c.x);
    // (x, y, z) -> (x, s, z) and (s, y, z): around s the triangles are (s, z, x) and (s, y, z).
    out.fan_pairs.push_back({c.z, c.x});
    out.fan_pairs.push_back({c.y, c.z});
  }
  out.fan_offsets.push_back(std::uint32_t(out.fan_pairs.size()));
}

bool far_enough(const glm::vec3& p, std::initializer_list<glm::vec3> corners, float min_distance) {
  for (const glm::vec3& c : corners)
    if (glm::distance(p, c) < min_distance) return false;
  return true;
}

void add_edge_sample(const FractureSurface& s, std::uint32_t edge, float t, float min_distance, SampleSet& out) {
  glm::uvec2 e = s.edges[edge];
  glm::vec3 a(s.positions[e.x]), b(s.positions[e.y]);
  t = kMinWeight + (1.0f - 2.0f * kMinWeight) * t;
  glm::vec3 p = (1.0f - t) * a + t * b;
  if (!far_enough(p, {a, b}, min_distance)) return;
  out.points.push_back(glm::vec4(p, 1.0f));
  out.requests.push_back({SplitRequest::kEdge, edge, glm::vec3(1.0f - t, t, 0.0f)});
  add_edge_fan(s, edge, out);
}

void add_face_sample(const FractureSurface& s, std::uint32_t f, std::uint64_t seed, std::uint32_t it,
                     float min_distance, SampleSet& out) {
  glm::uvec4 v = s.faces[f];
  glm::vec3 a(s.positions[v.x]), b(s.positions[v.y]), c(s.positions[v.z]);
  float r1 = sample_uniform(seed, it, f, 0), r2 = sample_uniform(seed, it, f, 1);
  float q = std::sqrt(r1);
  // Uniform over the triangle shrunk toward its centroid so that every weight is at least
  // kMinWeight: a sample near an edge would make a sliver that no flip can repair once it moves.
  glm::vec3 w = kMinWeight + (1.0f - 3.0f * kMinWeight) * glm::vec3(1.0f - q, q * (1.0f - r2), q * r2);
  glm::vec3 p = w.x * a + w.y * b + w.z * c;
  if (!far_enough(p, {a, b, c}, min_distance)) return;
  out.points.push_back(glm::vec4(p, 1.0f));
  out.requests.push_back({SplitRequest::kFace, f, w});
  out.fan_pairs.push_back({v.x, v.y});
  out.fan_pairs.push_back({v.y, v.z});
  out.fan_pairs.push_back({v.z, v.x});
  out.fan_offsets.push_back(std::uint32_t(out.fan_pairs.size()));
}

}  // namespace

std::uint32_t sample_hash(std::uint64_t seed, std::uint32_t iteration, std::uint32_t element, std::uint32_t stream) {
  std::uint32_t h = mix32(std::uint32_t(seed) ^ 0x9e3779b9U);
  h = mix32(h ^ std::uint32_t(seed >> 32));
  h = mix32(h ^ iteration);
  h = mix32(h ^ element);
  return mix32(h ^ stream);
}

float sample_uniform(std::uint64_t seed, std::uint32_t iteration, std::uint32_t element, std::uint32_t stream) {
  return float(sample_hash(seed, iteration, element, stream) >> 8) * (1.0f / 16777216.0f);
}

namespace {

void add_sample_of_face(const FractureSurface& s, std::uint32_t f, std::uint64_t seed, std::uint32_t it,
                        float min_distance, float rim_min_distance, SampleSet& out) {
  std::uint32_t boundary[3], nb = 0;
  for (int k = 0; k < 3; ++k)
    if (s.edge_special[s.face_edges[3 * f + k]] == kEdgeBoundary) boundary[nb++] = s.face_edges[3 * f + k];
  if (nb == 0) return add_face_sample(s, f, seed, it, min_distance, out);
  const std::uint32_t pick = boundary[sample_hash(seed, it, f, 2) % nb];
  add_edge_sample(s, pick, sample_uniform(seed, it, f, 0), std::max(min_distance, rim_min_distance), out);
}

// Appends `part` to `out`, its fans after out's.
void append(SampleSet& out, const SampleSet& part) {
  const std::uint32_t base = std::uint32_t(out.fan_pairs.size());
  out.points.insert(out.points.end(), part.points.begin(), part.points.end());
  out.requests.insert(out.requests.end(), part.requests.begin(), part.requests.end());
  out.fan_pairs.insert(out.fan_pairs.end(), part.fan_pairs.begin(), part.fan_pairs.end());
  for (std::size_t k = 1; k < part.fan_offsets.size(); ++k) out.fan_offsets.push_back(base + part.fan_offsets[k]);
}

// Threads drawing the face samples (each face's sample depends only on the hash: the set is the
// same for any count).

}  // namespace

SampleSet draw_samples(const FractureSurface& s, std::uint64_t seed, std::uint32_t it, float min_distance,
                       float rim_min_distance) {
  SampleSet out;
  const std::uint32_t nf = std::uint32_t(s.faces.size());
  for (std::uint32_t e = 0; e < s.edges.size(); ++e)
    if (s.edge_special[e] == kEdgeNonManifold) add_edge_sample(s, e, sample_uniform(seed, it, nf + e, 0), min_distance, out);
  const std::size_t chunks = chunk_count(nf, 8192);
  std::vector<SampleSet> parts(chunks);
  parallel_chunks(nf, chunks, default_threads(), [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (auto f = std::uint32_t(begin); f < end; ++f) add_sample_of_face(s, f, seed, it, min_distance, rim_min_distance, parts[c]);
  });
  for (const SampleSet& part : parts) append(out, part);
  return out;
}

}  // namespace fracref
