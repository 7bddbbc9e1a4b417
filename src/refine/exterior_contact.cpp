// faces_crossing_exterior (refine/exterior_contact.hpp).
#include "refine/exterior_contact.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"
#include "geom/predicates.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

bool on_rim(const rim::RimOnB& rim, std::uint32_t v) { return v < rim.on_b.size() && rim.on_b[v]; }

glm::dvec3 point(const std::vector<glm::vec4>& x, const rim::RimOnB& rim, std::uint32_t v) {
  return on_rim(rim, v) ? rim.at[v].point : glm::dvec3(glm::vec3(x[v]));
}

// Whether the face's longest edge reaches B from one of its corners (by the clearance bounds).
bool near_exterior(const glm::uvec4& f, const std::vector<glm::vec4>& x, const rim::RimOnB& rim,
                   const std::vector<float>& clearance) {
  double longest = 0.0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, double(glm::distance(glm::vec3(x[f[k]]), glm::vec3(x[f[(k + 1) % 3]]))));
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t v = f[k];
    if (on_rim(rim, v) || v >= clearance.size() || clearance[v] < 0.0f || double(clearance[v]) <= longest) return true;
  }
  return false;
}

bool face_crosses(const glm::uvec4& f, const std::vector<glm::vec4>& x, const rim::ExteriorMesh& m, const rim::RimOnB& rim) {
  std::array<const rim::Location*, 3> at{};
  for (int k = 0; k < 3; ++k) at[std::size_t(k)] = on_rim(rim, f[k]) ? &rim.at[f[k]] : nullptr;
  return rim::meets_exterior_off_rim(m, {point(x, rim, f.x), point(x, rim, f.y), point(x, rim, f.z)}, at);
}

}  // namespace

bool face_crosses_exterior(const glm::uvec4& face, const std::vector<glm::vec4>& x, const rim::ExteriorMesh& exterior,
                           const rim::RimOnB& rim, const std::vector<float>& clearance) {
  if (!near_exterior(face, x, rim, clearance)) return false;
  return face_crosses(face, x, exterior, rim);
}

std::vector<std::uint32_t> faces_crossing_exterior(const FractureSurface& s, const std::vector<glm::vec4>& x,
                                                   const rim::ExteriorMesh& exterior, const rim::RimOnB& rim,
                                                   const std::vector<float>& clearance,
                                                   const std::vector<std::uint32_t>* only) {
  std::vector<std::uint32_t> faces;
  if (only) faces = *only;
  else
    for (std::uint32_t f = 0; f < s.faces.size(); ++f)
      if (near_exterior(s.faces[f], x, rim, clearance)) faces.push_back(f);
  std::vector<char> crossing(faces.size(), 0);
  parallel_chunks(faces.size(), chunk_count(faces.size(), 256), default_threads(),
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t i = begin; i < end; ++i) crossing[i] = face_crosses(s.faces[faces[i]], x, exterior, rim);
                  });
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (crossing[i]) out.push_back(faces[i]);
  return out;
}

}  // namespace fracref
