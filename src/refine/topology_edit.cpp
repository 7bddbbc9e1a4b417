#include "refine/topology_edit.hpp"

#include <algorithm>
#include <map>

#include "geom/intersect.hpp"
#include "util/error.hpp"

namespace fracref {

RefinementTree RefinementTree::identity(std::size_t n) {
  RefinementTree t;
  t.parents.resize(n);
  t.weights.assign(n, glm::vec3(1.0f, 0.0f, 0.0f));
  for (std::uint32_t i = 0; i < n; ++i) t.parents[i] = glm::uvec3(i);
  return t;
}

std::vector<std::pair<std::uint32_t, double>> RefinementTree::leaf_weights(std::uint32_t v) const {
  std::map<std::uint32_t, double> acc;
  std::vector<std::pair<std::uint32_t, double>> stack{{v, 1.0}};
  while (!stack.empty()) {
    auto [u, w] = stack.back();
    stack.pop_back();
    if (parents[u] == glm::uvec3(u)) {
      acc[u] += w;
      continue;
    }
    for (int k = 0; k < 3; ++k)
      if (weights[u][k] != 0.0f) stack.push_back({parents[u][k], w * weights[u][k]});
  }
  return {acc.begin(), acc.end()};
}

namespace {

std::uint32_t add_vertex(FractureSurface& s, RefinementTree& tree, glm::uvec3 parents, glm::vec3 w) {
  glm::vec3 p = w.x * glm::vec3(s.positions[parents.x]) + w.y * glm::vec3(s.positions[parents.y]) +
                w.z * glm::vec3(s.positions[parents.z]);
  s.positions.push_back(glm::vec4(p, 1.0f));
  s.vertex_flags.push_back(0u);
  tree.parents.push_back(parents);
  tree.weights.push_back(w);
  return std::uint32_t(s.positions.size() - 1);
}

// Appends face v split off face `from` (same pieces), recording where it came from.
void add_face(FractureSurface& s, glm::uvec3 v, std::uint32_t from, std::vector<std::uint32_t>& origin) {
  s.faces.push_back(glm::uvec4(v, 0u));
  s.face_pieces.push_back(s.face_pieces[from]);
  origin.push_back(from);
}

void split_face(FractureSurface& s, RefinementTree& tree, const SplitRequest& r, std::vector<std::uint32_t>& origin) {
  glm::uvec4 f = s.faces[r.element];
  std::uint32_t v = add_vertex(s, tree, glm::uvec3(f), r.weights);
  s.faces[r.element] = glm::uvec4(f.x, f.y, v, 0u);
  add_face(s, {f.y, f.z, v}, r.element, origin);
  add_face(s, {f.z, f.x, v}, r.element, origin);
}

void split_edge(FractureSurface& s, RefinementTree& tree, const SplitRequest& r, std::vector<std::uint32_t>& origin) {
  glm::uvec2 e = s.edges[r.element];
  std::uint32_t v = add_vertex(s, tree, glm::uvec3(e.x, e.y, e.x), r.weights);
  for (std::uint32_t k = s.ef_offsets[r.element]; k < s.ef_offsets[r.element + 1]; ++k) {
    std::uint32_t fi = s.ef_faces[k];
    glm::uvec4 f = s.faces[fi];
    // Rotate so that the split edge is (x, y) in the face's own traversal order.
    glm::uvec3 c(f);
    for (int rot = 0; rot < 3; ++rot) {
      bool match = (c.x == e.x && c.y == e.y) || (c.x == e.y && c.y == e.x);
      if (match) break;
      c = glm::uvec3(c.y, c.z, c.x);
    }
    s.faces[fi] = glm::uvec4(c.x, v, c.z, 0u);
    add_face(s, {v, c.y, c.z}, fi, origin);
  }
}

}  // namespace

std::size_t apply_splits(FractureSurface& s, RefinementTree& tree, const std::vector<SplitRequest>& requests,
                         const std::vector<glm::vec3>* positions, std::vector<std::uint32_t>* deferred_origin) {
  const std::size_t before = s.positions.size(), first_face = s.faces.size();
  std::vector<std::uint32_t> own_origin;
  std::vector<std::uint32_t>& origin = deferred_origin ? *deferred_origin : own_origin;
  // Room for the new vertices and faces at once (a face split adds two faces, an edge split one
  // per face on the edge): a large batch grown split by split copied the arrays several times.
  // The room grows at least geometrically, so that many small batches (the rim chords' and
  // tucking passes) do not each copy the arrays for a few splits.
  std::size_t new_faces = 0;
  for (const SplitRequest& r : requests)
    new_faces += r.kind == SplitRequest::kFace ? 2 : s.ef_offsets[r.element + 1] - s.ef_offsets[r.element];
  auto room = [](auto& v, std::size_t more) {
    if (v.size() + more > v.capacity()) v.reserve(std::max(v.size() + more, 2 * v.capacity()));
  };
  room(s.positions, requests.size());
  room(s.vertex_flags, requests.size());
  room(tree.parents, requests.size());
  room(tree.weights, requests.size());
  room(s.faces, new_faces);
  room(s.face_pieces, new_faces);
  room(origin, new_faces);
  for (std::size_t k = 0; k < requests.size(); ++k) {
    const SplitRequest& r = requests[k];
    if (r.kind == SplitRequest::kFace) split_face(s, tree, r, origin);
    else split_edge(s, tree, r, origin);
    if (positions) s.positions.back() = glm::vec4((*positions)[k], 1.0f);
  }
  if (deferred_origin) rebuild_edge_table(s);
  else rebuild_after_splits(s, before, first_face, origin);
  return s.positions.size() - before;
}

FractureSurface split_preview(const FractureSurface& s, const std::vector<SplitRequest>& requests,
                              const std::vector<glm::vec3>& positions, RefinementTree* parents) {
  FractureSurface t = primary_copy(s);
  t.edges = s.edges;  // what split_edge reads
  t.ef_offsets = s.ef_offsets;
  t.ef_faces = s.ef_faces;
  RefinementTree scratch;  // add_vertex records the new vertices' parents
  scratch.parents.resize(s.positions.size());
  scratch.weights.resize(s.positions.size());
  std::vector<std::uint32_t> origin;
  for (std::size_t k = 0; k < requests.size(); ++k) {
    const SplitRequest& r = requests[k];
    if (r.kind == SplitRequest::kFace) split_face(t, scratch, r, origin);
    else split_edge(t, scratch, r, origin);
    t.positions.back() = glm::vec4(positions[k], 1.0f);
    if (r.kind == SplitRequest::kEdge && s.edge_special[r.element] == kEdgeBoundary) t.vertex_flags.back() |= kVertexBoundary;
  }
  rebuild_edge_table(t);
  if (parents) *parents = std::move(scratch);
  return t;
}

bool flip_candidates(const FractureSurface& s, std::uint32_t edge, glm::uvec2& opposite, glm::uvec2& faces) {
  return flip_quad(s, edge, opposite, faces) && find_edge(s, opposite.x, opposite.y) == kNoEdge;
}

bool flip_quad(const FractureSurface& s, std::uint32_t edge, glm::uvec2& opposite, glm::uvec2& faces) {
  if (s.edge_special[edge] != kEdgeRegular) return false;
  std::uint32_t f1 = s.ef_faces[s.ef_offsets[edge]], f2 = s.ef_faces[s.ef_offsets[edge] + 1];
  if (s.face_pieces[f1] != s.face_pieces[f2]) return false;
  glm::uvec2 e = s.edges[edge];
  // Rotates face fi to start at `first`; false when the face does not hold it (stale adjacency).
  auto rotate_to = [&](std::uint32_t fi, std::uint32_t first, glm::uvec3& c) {
    c = glm::uvec3(s.faces[fi]);
    for (int k = 0; k < 3 && c.x != first; ++k) c = glm::uvec3(c.y, c.z, c.x);
    return c.x == first;
  };
  glm::uvec3 a, b;
  if (!rotate_to(f1, e.x, a)) return false;  // (e.x, ?, ?)
  if (a.y != e.y) {                          // f1 traverses e.y -> e.x: swap roles
    std::swap(f1, f2);
    if (!rotate_to(f1, e.x, a) || a.y != e.y) return false;  // inconsistent winding
  }
  if (!rotate_to(f2, e.y, b) || b.y != e.x) return false;
  opposite = {a.z, b.z};
  faces = {f1, f2};
  return a.z != b.z;
}

bool flip_edge(FractureSurface& s, std::uint32_t edge) {
  glm::uvec2 cd, ff;
  if (!flip_candidates(s, edge, cd, ff)) return false;
  glm::uvec2 e = s.edges[edge];  // f1 = (a, b, c) with a = e.x, b = e.y; f2 = (b, a, d)
  s.faces[ff.x] = glm::uvec4(cd.x, e.x, cd.y, 0u);
  s.faces[ff.y] = glm::uvec4(cd.y, e.y, cd.x, 0u);
  return true;
}

// The faces the requests make, queried against the faces of S they leave as they are: a face they
// replace would meet its own children.
std::vector<char> splits_that_cross(const FractureSurface& s, const std::vector<SplitRequest>& requests,
                                    const std::vector<glm::vec3>& positions) {
  const auto base = static_cast<std::uint32_t>(s.positions.size());
  std::vector<glm::dvec3> p(base + requests.size());
  for (std::uint32_t v = 0; v < base; ++v) p[v] = glm::dvec3(glm::vec3(s.positions[v]));
  std::vector<TriangleIds> tris;
  std::vector<std::size_t> owner;
  std::vector<char> replaced(s.faces.size(), 0);
  for (std::size_t k = 0; k < requests.size(); ++k) {
    const SplitRequest& r = requests[k];
    const auto m = base + static_cast<std::uint32_t>(k);
    p[m] = glm::dvec3(positions[k]);
    auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) { tris.push_back({a, b, c}), owner.push_back(k); };
    if (r.kind == SplitRequest::kFace) {
      const glm::uvec4 f = s.faces[r.element];
      replaced[r.element] = 1;
      add(f.x, f.y, m), add(f.y, f.z, m), add(f.z, f.x, m);
      continue;
    }
    const glm::uvec2 e = s.edges[r.element];
    for (std::uint32_t i = s.ef_offsets[r.element]; i < s.ef_offsets[r.element + 1]; ++i) {
      const glm::uvec4 f = s.faces[s.ef_faces[i]];
      const std::uint32_t z = f.x + f.y + f.z - e.x - e.y;
      replaced[s.ef_faces[i]] = 1;
      add(e.x, m, z), add(m, e.y, z);
    }
  }
  std::vector<char> crossing(requests.size(), 0);
  if (tris.empty()) return crossing;
  SelfIntersectionOptions o;
  o.query_faces = tris.size();
  for (std::uint32_t f = 0; f < s.faces.size(); ++f)
    if (!replaced[f]) tris.push_back({s.faces[f].x, s.faces[f].y, s.faces[f].z});
  for (const auto& [i, j] : find_self_intersections(p, tris, o)) {
    crossing[owner[i]] = 1;
    if (j < o.query_faces) crossing[owner[j]] = 1;
  }
  return crossing;
}

}  // namespace fracref
