// Material-aware piece layouts: the Voronoi cells of the sites under a travel cost that is high
// in weak material, so the cells meet (and the coarse cracks run) where the material is weak.
#include <algorithm>
#include <limits>
#include <memory>
#include <queue>
#include <string>
#include <utility>

#include "field/noise.hpp"
#include "field/procedural.hpp"
#include "scenegen/scenegen_internal.hpp"

namespace fracref::scenegen_detail {
namespace {

constexpr int kSamples = 8;  // cost samples along the segment joining two tets' centroids

std::uint32_t nearest_tet(const TetSet& set, const glm::dvec3& p) {
  std::uint32_t best = 0;
  double d_best = std::numeric_limits<double>::infinity();
  for (std::uint32_t t = 0; t < set.tets.size(); ++t)
    if (const double d = glm::distance(tet_centroid(set, t), p); d < d_best) d_best = d, best = t;
  return best;
}

}  // namespace

std::vector<double> crossing_costs(const TetSet& set, const TetFaces& faces, const CrackCost& cost) {
  std::vector<double> out(faces.interior_tets.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const glm::dvec3 a = tet_centroid(set, faces.interior_tets[i].x), b = tet_centroid(set, faces.interior_tets[i].y);
    double most = 0.0;
    for (int k = 0; k < kSamples; ++k) most = std::max(most, cost(a + (b - a) * ((k + 0.5) / kSamples)));
    out[i] = glm::distance(a, b) * most;
  }
  return out;
}

// Dijkstra from every site at once; a tet takes the label of the site that reaches it first
// (ties to the tet settled first: the queue orders by cost, then tet), so the result is one.
std::vector<int> geodesic_labels(const TetSet& set, const TetFaces& faces, const std::vector<glm::dvec3>& sites,
                                 const std::vector<double>& costs) {
  const std::size_t n = set.tets.size();
  std::vector<std::vector<std::pair<std::uint32_t, double>>> next(n);
  for (std::size_t i = 0; i < faces.interior_tets.size(); ++i) {
    const glm::uvec2 t = faces.interior_tets[i];
    next[t.x].push_back({t.y, costs[i]}), next[t.y].push_back({t.x, costs[i]});
  }
  std::vector<double> reach(n, std::numeric_limits<double>::infinity());
  std::vector<int> labels(n, -1);
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  for (std::size_t s = 0; s < sites.size(); ++s) {
    const std::uint32_t t = nearest_tet(set, sites[s]);
    if (labels[t] >= 0) continue;
    reach[t] = 0.0, labels[t] = int(s);
    open.push({0.0, t});
  }
  while (!open.empty()) {
    const auto [d, t] = open.top();
    open.pop();
    if (d > reach[t]) continue;
    for (const auto& [u, c] : next[t])
      if (d + c < reach[u]) reach[u] = d + c, labels[u] = labels[t], open.push({reach[u], u});
  }
  for (int& l : labels) l = std::max(l, 0);  // a tet no site reaches (none in a connected set)
  return labels;
}

Strength material_strength(const std::string& field_type, std::uint64_t seed, const glm::dvec3& lo,
                           const glm::dvec3& hi) {
  FieldSpec spec;
  spec.type = field_type;
  spec.seed = seed;
  spec.object_min = lo, spec.object_max = hi;
  validate_field_spec(spec);
  auto noise = std::make_shared<PerlinNoise>(seed);
  return [spec, noise](const glm::dvec3& p) { return strength_at(spec, *noise, p); };
}

CrackCost weakness_cost(Strength zeta) {
  return [zeta = std::move(zeta)](const glm::dvec3& p) { return 1.0 / (zeta(p) + kCostFloor); };
}

}  // namespace fracref::scenegen_detail
