// Piece layouts: seeded Voronoi cells on the tets, tidied into clean solid pieces.
#include <algorithm>
#include <limits>
#include <map>
#include <numeric>

#include "scenegen/scenegen_internal.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {
namespace {

class Roots {
 public:
  explicit Roots(std::size_t n) : root_(n) { std::iota(root_.begin(), root_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (root_[x] != x) x = root_[x] = root_[root_[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    root_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<std::uint32_t> root_;
};

// Relabels every face-connected part of a label as a label of its own, numbered by lowest tet;
// returns the parts' sizes.
std::vector<std::size_t> split_parts(const TetFaces& faces, std::vector<int>& labels) {
  Roots roots(labels.size());
  for (const glm::uvec2& t : faces.interior_tets)
    if (labels[t.x] == labels[t.y]) roots.unite(t.x, t.y);
  std::vector<int> part(labels.size(), -1);
  std::vector<std::size_t> sizes;
  for (std::uint32_t t = 0; t < labels.size(); ++t) {
    const std::uint32_t r = roots.find(t);
    if (part[r] < 0) {
      part[r] = int(sizes.size());
      sizes.push_back(0);
    }
    labels[t] = part[r];
    ++sizes[part[r]];
  }
  return sizes;
}

// Merges the first part smaller than min_tets that has a neighbour into the neighbour it shares
// most faces with (ties to the lowest label). False when there is none.
bool merge_small(const TetFaces& faces, std::vector<int>& labels, const std::vector<std::size_t>& sizes,
                 std::size_t min_tets) {
  for (int p = 0; p < int(sizes.size()); ++p) {
    if (sizes[p] >= min_tets) continue;
    std::map<int, std::size_t> shared;
    for (const glm::uvec2& t : faces.interior_tets) {
      const int a = labels[t.x], b = labels[t.y];
      if (a != b && (a == p || b == p)) ++shared[a == p ? b : a];
    }
    if (shared.empty()) continue;
    int into = shared.begin()->first;
    for (const auto& [label, n] : shared)
      if (n > shared[into]) into = label;
    for (int& l : labels)
      if (l == p) l = into;
    return true;
  }
  return false;
}

// Per piece, where its boundary (hull faces and faces to other pieces) is not a 2-manifold.
std::vector<std::pair<std::uint32_t, std::uint32_t>> piece_defects(const TetFaces& faces,
                                                                  const std::vector<int>& labels, int pieces) {
  std::vector<std::vector<glm::uvec3>> boundary(pieces);
  for (std::size_t i = 0; i < faces.hull.size(); ++i) boundary[labels[faces.hull_tet[i]]].push_back(faces.hull[i]);
  for (std::size_t i = 0; i < faces.interior.size(); ++i) {
    const int a = labels[faces.interior_tets[i].x], b = labels[faces.interior_tets[i].y];
    if (a == b) continue;
    const glm::uvec3 f = faces.interior[i];
    boundary[a].push_back(f);
    boundary[b].push_back({f.x, f.z, f.y});
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> bad;
  for (const auto& b : boundary) {
    const auto d = surface_defects(b);
    bad.insert(bad.end(), d.begin(), d.end());
  }
  // A cut ends on the exterior in one face per exterior edge: where two or more cut faces
  // meet at an exterior edge, the fracture surface could not tell which pieces lie between
  // them (it would read the edge as inside the material).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> hull_edges, cut_edges;
  for (const glm::uvec3& f : faces.hull)
    for (int e = 0; e < 3; ++e) hull_edges.push_back(std::minmax(f[e], f[(e + 1) % 3]));
  std::sort(hull_edges.begin(), hull_edges.end());
  for (std::size_t i = 0; i < faces.interior.size(); ++i)
    if (labels[faces.interior_tets[i].x] != labels[faces.interior_tets[i].y])
      for (int e = 0; e < 3; ++e) {
        const std::pair<std::uint32_t, std::uint32_t> edge = std::minmax(faces.interior[i][e], faces.interior[i][(e + 1) % 3]);
        if (std::binary_search(hull_edges.begin(), hull_edges.end(), edge)) cut_edges.push_back(edge);
      }
  std::sort(cut_edges.begin(), cut_edges.end());
  for (std::size_t i = 1; i < cut_edges.size(); ++i)
    if (cut_edges[i] == cut_edges[i - 1]) bad.push_back(cut_edges[i]);
  std::sort(bad.begin(), bad.end());
  bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
  return bad;
}

// The label with the most votes, ties to the lowest.
int most_votes(const std::map<int, int>& votes) {
  int winner = votes.begin()->first;
  for (const auto& [label, n] : votes)
    if (n > votes.at(winner)) winner = label;
  return winner;
}

// The tets around each defect take the label most of them have (ties to the lowest label), or
// with `lowest`, the lowest label among them: labels then only decrease, so repeated rounds end.
void fill_defects(const TetSet& set, const VertexTets& vt, std::vector<int>& labels,
                  const std::vector<std::pair<std::uint32_t, std::uint32_t>>& defects, bool lowest) {
  for (const auto& [a, b] : defects) {
    std::vector<std::uint32_t> around;
    for (std::uint32_t i = vt.offsets[a]; i < vt.offsets[a + 1]; ++i) {
      const glm::uvec4& t = set.tets[vt.tets[i]];
      if (t.x == b || t.y == b || t.z == b || t.w == b) around.push_back(vt.tets[i]);
    }
    std::map<int, int> votes;
    for (const std::uint32_t t : around) ++votes[labels[t]];
    const int winner = lowest ? votes.begin()->first : most_votes(votes);
    for (const std::uint32_t t : around) labels[t] = winner;
  }
}

}  // namespace

std::vector<glm::dvec3> spread_sites(const TetSet& set, int count, Rng& rng,
                                     const std::function<double(const glm::dvec3&)>& spacing) {
  std::vector<glm::dvec3> sites;
  const std::size_t n = set.tets.size();
  for (int s = 0; s < count; ++s) {
    glm::dvec3 best(0.0);
    double best_score = -1.0;
    for (int c = 0; c < 12; ++c) {
      const glm::dvec3 p = tet_centroid(set, std::uint32_t(rng.next() % n));
      double d = std::numeric_limits<double>::infinity();
      for (const glm::dvec3& q : sites) d = std::min(d, glm::distance(p, q));
      const double score = sites.empty() ? 0.0 : d / spacing(p);
      if (score > best_score) best_score = score, best = p;
    }
    sites.push_back(best);
  }
  return sites;
}

std::vector<int> voronoi_labels(const TetSet& set, const std::vector<glm::dvec3>& sites) {
  std::vector<int> labels(set.tets.size(), 0);
  for (std::uint32_t t = 0; t < set.tets.size(); ++t) {
    const glm::dvec3 c = tet_centroid(set, t);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s < sites.size(); ++s) {
      const glm::dvec3 d = c - sites[s];
      const double q = glm::dot(d, d);
      if (q < best) best = q, labels[t] = int(s);
    }
  }
  return labels;
}

void whole_cells(std::vector<int>& labels, int cell_tets) {
  std::vector<int> own(labels.size() / std::size_t(cell_tets));  // each cell its own unit
  std::iota(own.begin(), own.end(), 0);
  whole_units(labels, cell_tets, own);
}

void whole_units(std::vector<int>& labels, int cell_tets, const std::vector<int>& units) {
  std::map<int, std::map<int, int>> votes;
  for (std::size_t c = 0; c < units.size(); ++c)
    for (std::size_t t = c * std::size_t(cell_tets); t < (c + 1) * std::size_t(cell_tets); ++t) ++votes[units[c]][labels[t]];
  for (std::size_t c = 0; c < units.size(); ++c) {
    const int label = most_votes(votes[units[c]]);
    std::fill(labels.begin() + std::ptrdiff_t(c * cell_tets), labels.begin() + std::ptrdiff_t((c + 1) * cell_tets), label);
  }
}

void tidy_labels(const TetSet& set, const TetFaces& faces, std::vector<int>& labels, std::size_t min_tets) {
  const VertexTets vt = vertex_tets(set);
  for (int round = 0; round < 1000; ++round) {
    const std::vector<std::size_t> sizes = split_parts(faces, labels);
    if (merge_small(faces, labels, sizes, min_tets)) continue;
    const auto defects = piece_defects(faces, labels, int(sizes.size()));
    if (defects.empty()) return;
    fill_defects(set, vt, labels, defects, round >= 10);
  }
  throw RunError("scenegen: the piece layout did not settle into clean pieces");
}

std::size_t cut_face_count(const TetFaces& faces, const std::vector<int>& labels) {
  std::size_t n = 0;
  for (const glm::uvec2& t : faces.interior_tets) n += labels[t.x] != labels[t.y];
  return n;
}

std::vector<int> best_layout(const TetSet& set, const TetFaces& faces, const std::vector<glm::dvec3>& sites, int k_lo,
                             int k_hi, std::size_t target, std::size_t min_tets, const std::vector<double>& costs,
                             int cell_tets, const std::vector<int>& units) {
  std::vector<int> best;
  std::size_t best_error = std::numeric_limits<std::size_t>::max();
  for (int k = k_lo; k <= k_hi && k <= int(sites.size()); ++k) {
    const std::vector<glm::dvec3> first(sites.begin(), sites.begin() + k);
    std::vector<int> labels = costs.empty() ? voronoi_labels(set, first) : geodesic_labels(set, faces, first, costs);
    if (cell_tets > 1) whole_cells(labels, cell_tets);
    if (!units.empty()) whole_units(labels, cell_tets, units);
    tidy_labels(set, faces, labels, min_tets);
    const std::size_t count = cut_face_count(faces, labels);
    const std::size_t error = count > target ? count - target : target - count;
    if (error < best_error) best_error = error, best = std::move(labels);
  }
  return best;
}

}  // namespace fracref::scenegen_detail
