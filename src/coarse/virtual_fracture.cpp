// The crack-front growth of virtual fracture on the faces of a tet mesh.
#include "coarse/virtual_fracture.hpp"

#include <algorithm>
#include <set>
#include <tuple>
#include <utility>

#include "util/error.hpp"

namespace fracref {
namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;

Edge make_edge(std::uint32_t a, std::uint32_t b) { return a < b ? Edge(a, b) : Edge(b, a); }

// Edges of the interior faces with their faces (CSR), whether each is on the hull, and the
// number of cut faces around each.
class FaceEdges {
 public:
  FaceEdges(const std::vector<glm::uvec3>& faces, const std::vector<glm::uvec3>& hull,
            const std::vector<std::uint8_t>& cut) {
    std::vector<std::pair<Edge, std::uint32_t>> uses;
    uses.reserve(faces.size() * 3);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
      for (int i = 0; i < 3; ++i) uses.emplace_back(make_edge(faces[f][i], faces[f][(i + 1) % 3]), f);
    std::sort(uses.begin(), uses.end());
    offsets.push_back(0);
    for (std::size_t i = 0; i < uses.size(); ++i) {
      if (i == 0 || uses[i].first != uses[i - 1].first) {
        if (i) offsets.push_back(std::uint32_t(i));
        edges.push_back(uses[i].first);
      }
      edge_faces.push_back(uses[i].second);
    }
    offsets.push_back(std::uint32_t(uses.size()));
    std::vector<Edge> hull_edges;
    for (const glm::uvec3& h : hull)
      for (int i = 0; i < 3; ++i) hull_edges.push_back(make_edge(h[i], h[(i + 1) % 3]));
    std::sort(hull_edges.begin(), hull_edges.end());
    on_hull.resize(edges.size());
    cut_count.assign(edges.size(), 0);
    for (std::size_t e = 0; e < edges.size(); ++e) {
      on_hull[e] = std::binary_search(hull_edges.begin(), hull_edges.end(), edges[e]);
      for (std::uint32_t k = offsets[e]; k < offsets[e + 1]; ++k) cut_count[e] += cut[edge_faces[k]] ? 1 : 0;
    }
  }

  std::uint32_t find(Edge e) const {
    return std::uint32_t(std::lower_bound(edges.begin(), edges.end(), e) - edges.begin());
  }
  bool is_front(std::uint32_t e) const { return !on_hull[e] && cut_count[e] == 1; }

  std::vector<Edge> edges;
  std::vector<std::uint32_t> offsets, edge_faces, cut_count;
  std::vector<bool> on_hull;
};

std::uint32_t third_corner(const glm::uvec3& f, const Edge& e) {
  for (int i = 0; i < 3; ++i)
    if (f[i] != e.first && f[i] != e.second) return f[i];
  return f.x;
}

struct Candidate {
  double dot = -2.0;
  std::uint32_t face = std::uint32_t(-1);
};

// The uncut face around front edge e best aligned with its one cut face.
Candidate best_continuation(const FaceEdges& g, std::uint32_t e, const std::vector<glm::dvec3>& p,
                            const std::vector<glm::uvec3>& faces, const std::vector<std::uint8_t>& cut) {
  const glm::dvec3 a = p[g.edges[e].first], b = p[g.edges[e].second];
  std::uint32_t crack = 0;
  for (std::uint32_t k = g.offsets[e]; k < g.offsets[e + 1]; ++k)
    if (cut[g.edge_faces[k]]) crack = g.edge_faces[k];
  // The cut face as (a, b, c) and a continuation as (b, a, d): wound consistently across the edge.
  const glm::dvec3 n_crack = glm::normalize(glm::cross(b - a, p[third_corner(faces[crack], g.edges[e])] - a));
  Candidate best;
  for (std::uint32_t k = g.offsets[e]; k < g.offsets[e + 1]; ++k) {
    const std::uint32_t f = g.edge_faces[k];
    if (cut[f]) continue;
    const glm::dvec3 n = glm::normalize(glm::cross(a - b, p[third_corner(faces[f], g.edges[e])] - b));
    const double d = glm::dot(n, n_crack);
    if (d > best.dot) best = {d, f};  // faces ascend within an edge: ties keep the lowest
  }
  if (best.face == std::uint32_t(-1)) throw RunError("virtual fracture: front edge has no uncut face");
  return best;
}

// Front edges ordered by their best candidate: best aligned first, then lowest face, then edge.
class FrontQueue {
 public:
  explicit FrontQueue(std::size_t edges) : entry_(edges), queued_(edges, false) {}
  void update(std::uint32_t e, const FaceEdges& g, const std::vector<glm::dvec3>& p, const std::vector<glm::uvec3>& faces,
              const std::vector<std::uint8_t>& cut) {
    if (queued_[e]) queue_.erase(entry_[e]), queued_[e] = false;
    if (!g.is_front(e)) return;
    const Candidate c = best_continuation(g, e, p, faces, cut);
    entry_[e] = {-c.dot, c.face, e};
    queue_.insert(entry_[e]);
    queued_[e] = true;
  }
  bool empty() const { return queue_.empty(); }
  std::uint32_t top_face() const { return std::get<1>(*queue_.begin()); }

 private:
  using Entry = std::tuple<double, std::uint32_t, std::uint32_t>;  // (-dot, face, edge)
  std::set<Entry> queue_;
  std::vector<Entry> entry_;
  std::vector<bool> queued_;
};

}  // namespace

VirtualFractureStats extend_cracks(const std::vector<glm::dvec3>& positions,
                                   const std::vector<glm::uvec3>& interior_faces,
                                   const std::vector<glm::uvec3>& hull_faces, std::vector<std::uint8_t>& cut) {
  if (cut.size() != interior_faces.size()) throw RunError("extend_cracks: one cut flag per interior face expected");
  for (const auto* list : {&interior_faces, &hull_faces})
    for (const glm::uvec3& f : *list)
      if (f.x >= positions.size() || f.y >= positions.size() || f.z >= positions.size())
        throw RunError("extend_cracks: face vertex out of range");
  FaceEdges g(interior_faces, hull_faces, cut);
  FrontQueue front(g.edges.size());
  for (std::uint32_t e = 0; e < g.edges.size(); ++e) front.update(e, g, positions, interior_faces, cut);
  VirtualFractureStats stats;
  while (!front.empty()) {
    const std::uint32_t f = front.top_face();
    cut[f] = 1;
    ++stats.faces_added;
    const glm::uvec3 t = interior_faces[f];
    stats.area_added += 0.5 * glm::length(glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]));
    // Cutting f changes the cut count of its own edges only, and no other edge's candidates.
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t e = g.find(make_edge(t[i], t[(i + 1) % 3]));
      ++g.cut_count[e];
      front.update(e, g, positions, interior_faces, cut);
    }
  }
  return stats;
}

}  // namespace fracref
