// build_pieces' retries (retries.hpp).
#include "pieces/retries.hpp"

#include <algorithm>
#include <set>

namespace fracref::pieces_detail {

std::string PokingOut::describe() const {
  const auto deepest = std::max_element(vertices.begin(), vertices.end(),
                                        [](const auto& a, const auto& b) { return a.second.depth < b.second.depth; });
  return "the faces of fracture surface vertex " + std::to_string(deepest->first) + " at " +
         format_point(deepest->second.at) + " poke out of the exterior by " + std::to_string(deepest->second.depth) +
         (vertices.size() > 1 ? " (the faces of " + std::to_string(vertices.size() - 1) + " more vertices poke out less)" : "");
}

bool Retries::next(const UntriangulatedFaces& failed, std::string& why) {
  for (const auto& face : failed.faces)
    if (!next(face)) {
      why = face.what;
      return false;
    }
  return true;
}

bool Retries::next(const UntriangulatedFaces::Face& failed) {
  if (failed.flap) {
    if (std::count(left_out.begin(), left_out.end(), failed.face)) return false;
    left_out.push_back(failed.face);
    return true;
  }
  const auto it = along_normal.find(failed.face);
  if (it == along_normal.end()) {
    along_normal.emplace(failed.face, push_rounds);
    return true;
  }
  if (it->second != push_rounds) {
    along_normal.erase(it);  // S was pushed since: the usual plane may do now
    return true;
  }
  // Neither plane works (the face stands at a slant to a curved B): its boundary edge is
  // contracted, the face with it.
  for (const auto& c :
       {std::pair{failed.boundary_edge.y, failed.boundary_edge.x}, std::pair{failed.boundary_edge.x, failed.boundary_edge.y}})
    if (!std::count(contractions.begin(), contractions.end(), c)) {
      contractions.push_back(c);
      return true;
    }
  return false;
}

bool Retries::next(const PokingOut& poking, std::string& why) {
  for (const auto& [v, p] : poking.vertices) {
    Push& push = pushed[v];
    const bool futile = push.distance > 0.0 && p.depth >= kFutilePush * push.last_depth;
    push.distance += kPushFactor * p.depth;
    push.direction = p.direction;
    push.last_depth = p.depth;
    if (!futile && push.distance <= p.limit && push_rounds < kMaxPushRounds) continue;
    // Pushed as far as it may go: the vertex is contracted into its nearest neighbour instead
    // (a sliver of S sticking out), or, when that was tried, into the next nearest.
    const auto untried = std::find_if(p.neighbours.begin(), p.neighbours.end(), [&](std::uint32_t w) {
      return !std::count(contractions.begin(), contractions.end(), std::pair{v, w});
    });
    if (untried == p.neighbours.end()) {
      why = "the faces of fracture surface vertex " + std::to_string(v) + " at " + format_point(p.at) +
            " poke out of the exterior by " + std::to_string(p.depth) +
            " (the fracture surface crosses the exterior near its rim), still after pushing it inward";
      return false;
    }
    contractions.emplace_back(v, *untried);
    pushed.erase(v);
  }
  ++push_rounds;
  return true;
}

bool Retries::next(const TracesCross& crossed, const std::vector<glm::dvec3>& x) {
  std::set<std::uint32_t> moved;  // one contraction per rim vertex and attempt
  bool added = false;
  for (const auto& [a, b] : crossed.pairs) {
    // Candidates in order: the shared vertex into its nearer, then its farther neighbour (a
    // zigzag), else either end of the shorter edge, then of the longer one.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> options;
    if (a == b) {  // one trace crossing itself: the edge goes
      options = {{a.y, a.x}, {a.x, a.y}};
    } else if (a.x == b.x || a.x == b.y || a.y == b.x || a.y == b.y) {
      const std::uint32_t v = (a.x == b.x || a.x == b.y) ? a.x : a.y;
      std::uint32_t p = a.x == v ? a.y : a.x, q = b.x == v ? b.y : b.x;
      if (glm::length(x[q] - x[v]) < glm::length(x[p] - x[v])) std::swap(p, q);
      options = {{v, p}, {v, q}};
    } else {
      const bool a_shorter = glm::length(x[a.x] - x[a.y]) <= glm::length(x[b.x] - x[b.y]);
      const glm::uvec2 e = a_shorter ? a : b, f = a_shorter ? b : a;
      options = {{e.y, e.x}, {e.x, e.y}, {f.y, f.x}, {f.x, f.y}};
    }
    for (const auto& c : options) {
      if (moved.count(c.first) || moved.count(c.second) || std::count(contractions.begin(), contractions.end(), c)) continue;
      contractions.push_back(c);
      moved.insert(c.first), moved.insert(c.second);
      added = true;
      break;
    }
  }
  return added;
}

bool Retries::next(const Folded& folded, std::string& why) {
  std::set<std::uint32_t> gone;
  for (const auto& c : contractions) gone.insert(c.first);
  const Folded::Vertex* best = nullptr;
  std::uint32_t best_v = 0;
  for (const auto& [v, p] : folded.vertices)
    if (!gone.count(v) && !gone.count(p.nearest) && (!best || p.shortest < best->shortest)) best = &p, best_v = v;
  if (best) {
    contractions.emplace_back(best_v, best->nearest);
    return true;
  }
  for (const auto& [v, p] : folded.vertices) {
    double& fraction = relaxed[v];
    if (fraction >= 1.0) {
      why = std::string(folded.what()) + "; still after moving fracture surface vertex " + std::to_string(v) + " at " +
            format_point(p.at) + " to the centroid of its neighbours";
      return false;
    }
    fraction = std::min(1.0, fraction + kRelaxStep);
  }
  return true;
}

}  // namespace fracref::pieces_detail
