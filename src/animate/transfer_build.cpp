// build_transfer: the slots of every piece, the anchors, and each slot's terms (steps 2 and 3).
#include <algorithm>
#include <cmath>

#include "animate/animate_internal.hpp"
#include "geom/bvh.hpp"
#include "util/error.hpp"

namespace fracref {
namespace animate_detail {

CoarseCopies coarse_copies(const CoarseModel& model) {
  const FractureSurface& s = model.surface;
  CoarseCopies out;
  for (std::size_t v = 0; v < s.vertex_count(); ++v) {
    for (std::uint32_t e = s.copy_offsets[v]; e < s.copy_offsets[v + 1]; ++e)
      out.copies.emplace_back(s.copies[e].x, model.surface_copy_model_vertex[e]);
    out.offsets.push_back(std::uint32_t(out.copies.size()));
  }
  return out;
}

std::uint32_t copy_of(const CoarseCopies& c, std::uint32_t s, int piece) {
  for (std::uint32_t e = c.offsets[s]; e < c.offsets[s + 1]; ++e)
    if (int(c.copies[e].x) == piece) return c.copies[e].y;
  return UINT32_MAX;
}

std::vector<std::vector<std::pair<std::uint32_t, double>>> all_leaves(const RefinementTree& tree, std::size_t count,
                                                                      std::size_t coarse_count) {
  std::vector<std::vector<std::pair<std::uint32_t, double>>> out(count);
  for (std::uint32_t v = 0; v < count; ++v) {
    const glm::uvec3 parents = tree.parents[v];
    std::vector<std::pair<std::uint32_t, double>> acc;
    if (parents == glm::uvec3(v)) {
      acc.push_back({v, 1.0});
    } else if (parents.x < v && parents.y < v && parents.z < v) {
      for (int k = 0; k < 3; ++k) {
        if (tree.weights[v][k] == 0.0f) continue;
        for (const auto& [leaf, w] : out[parents[k]]) acc.push_back({leaf, w * double(tree.weights[v][k])});
      }
    } else {
      acc = tree.leaf_weights(v);  // not in creation order: walk the tree
    }
    std::sort(acc.begin(), acc.end());
    auto& merged = out[v];
    for (const auto& [leaf, w] : acc) {
      if (leaf >= coarse_count)
        throw RunError("animate: refined vertex " + std::to_string(v) + " has leaf " + std::to_string(leaf) +
                       ", not a coarse fracture-surface vertex (" + std::to_string(coarse_count) + ")");
      if (!merged.empty() && merged.back().first == leaf) merged.back().second += w;
      else merged.push_back({leaf, w});
    }
    std::erase_if(merged, [](const auto& lw) { return std::abs(lw.second) < 1e-12; });
  }
  return out;
}

std::uint32_t find_anchor(const AnimationTransfer& transfer, std::uint32_t model_vertex, int piece) {
  const glm::uvec2 key(model_vertex, std::uint32_t(piece));
  auto less = [](const glm::uvec2& a, const glm::uvec2& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; };
  auto it = std::lower_bound(transfer.anchors.begin(), transfer.anchors.end(), key, less);
  return it != transfer.anchors.end() && *it == key ? std::uint32_t(it - transfer.anchors.begin()) : UINT32_MAX;
}

}  // namespace animate_detail

namespace {

using namespace animate_detail;

void check_inputs(const CoarseModel& model, const CoarseAnimation& animation, const RefinementTree& tree,
                  const PieceSet& pieces) {
  if (animation.frames.empty()) throw RunError("animate: the coarse animation has no frame");
  for (std::size_t t = 0; t < animation.frames.size(); ++t)
    if (animation.frames[t].size() != model.vertices.size())
      throw RunError("animate: frame " + std::to_string(t) + " has " + std::to_string(animation.frames[t].size()) +
                     " vertices, the coarse model " + std::to_string(model.vertices.size()));
  if (!animation.piece_transforms.empty()) {
    bool ok = animation.piece_transforms.size() == animation.frames.size();
    for (const auto& f : animation.piece_transforms) ok = ok && f.size() == std::size_t(model.piece_count);
    if (!ok) throw RunError("animate: the rigid transforms are not one per frame and piece");
  }
  if (pieces.pieces.size() != std::size_t(model.piece_count))
    throw RunError("animate: " + std::to_string(pieces.pieces.size()) + " piece meshes for " +
                   std::to_string(model.piece_count) + " coarse pieces");
  if (tree.parents.size() < pieces.s_vertex_count || tree.weights.size() != tree.parents.size())
    throw RunError("animate: the refinement tree covers " + std::to_string(tree.parents.size()) + " vertices, the pieces use " +
                   std::to_string(pieces.s_vertex_count) + " fracture-surface vertices");
}

PieceLayout make_layout(const PieceSet& pieces) {
  PieceLayout layout;
  for (const PieceSet::Piece& piece : pieces.pieces) {
    std::vector<std::uint32_t> used;
    for (const auto& t : piece.triangles) used.insert(used.end(), t.begin(), t.end());
    std::sort(used.begin(), used.end());
    used.erase(std::unique(used.begin(), used.end()), used.end());
    layout.offsets.push_back(layout.offsets.back() + std::uint32_t(used.size()));
    layout.vertices.push_back(std::move(used));
  }
  return layout;
}

// Per piece, its coarse boundary on model vertex ids: hull faces, then its side of S wound outward.
std::vector<std::vector<Tri>> coarse_boundary(const CoarseModel& model, const CoarseCopies& copies) {
  std::vector<std::vector<Tri>> out(std::size_t(model.piece_count));
  for (std::size_t f = 0; f < model.hull.size(); ++f)
    out[std::size_t(model.hull_piece[f])].push_back({model.hull[f].x, model.hull[f].y, model.hull[f].z});
  const FractureSurface& s = model.surface;
  for (std::size_t f = 0; f < s.faces.size(); ++f)
    for (int side = 0; side < 2; ++side) {
      const int p = side == 0 ? s.face_pieces[f].x : s.face_pieces[f].y;
      Tri t;
      for (int k = 0; k < 3; ++k) t[k] = copy_of(copies, s.faces[f][k], p);
      if (t[0] == UINT32_MAX || t[1] == UINT32_MAX || t[2] == UINT32_MAX)
        throw RunError("animate: coarse S face " + std::to_string(f) + " has a corner with no copy in piece " + std::to_string(p));
      if (side == 0) std::swap(t[1], t[2]);  // the front piece sees the face from its normal side
      out[std::size_t(p)].push_back(t);
    }
  return out;
}

void make_anchors(AnimationTransfer& tr, const std::vector<std::vector<Tri>>& boundary) {
  for (std::size_t p = 0; p < boundary.size(); ++p)
    for (const Tri& t : boundary[p])
      for (std::uint32_t m : t) tr.anchors.emplace_back(m, std::uint32_t(p));
  auto less = [](const glm::uvec2& a, const glm::uvec2& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; };
  std::sort(tr.anchors.begin(), tr.anchors.end(), less);
  tr.anchors.erase(std::unique(tr.anchors.begin(), tr.anchors.end()), tr.anchors.end());
}

// Closest-point trees of each piece's coarse boundary, on anchor ids.
struct PieceBoundaries {
  std::vector<std::vector<Tri>> anchor_tris;
  std::vector<Bvh> trees;
};

PieceBoundaries boundary_trees(const AnimationTransfer& tr, const CoarseModel& model,
                               const std::vector<std::vector<Tri>>& boundary) {
  PieceBoundaries out;
  std::vector<glm::dvec3> positions;
  for (const glm::uvec2& a : tr.anchors) positions.push_back(model.vertices[a.x]);
  for (std::size_t p = 0; p < boundary.size(); ++p) {
    if (boundary[p].empty()) throw RunError("animate: piece " + std::to_string(p) + " has no coarse boundary");
    std::vector<Tri> tris;
    for (const Tri& t : boundary[p]) {
      Tri a;
      for (int k = 0; k < 3; ++k) a[k] = find_anchor(tr, t[k], int(p));
      tris.push_back(a);
    }
    out.trees.push_back(build_bvh(positions, tris));
    out.anchor_tris.push_back(std::move(tris));
  }
  return out;
}

void add_nearest_terms(AnimationTransfer& tr, const PieceBoundaries& b, int piece, const glm::dvec3& x) {
  const ClosestPoint c = closest_point(b.trees[std::size_t(piece)], x);
  const Tri& t = b.anchor_tris[std::size_t(piece)][c.triangle];
  for (int k = 0; k < 3; ++k)
    if (c.barycentric[k] != 0.0) tr.terms.push_back({t[k], c.barycentric[k], x - c.point});
}

// Terms of fracture vertex v seen from `piece`; false when no leaf is usable.
bool add_leaf_terms(AnimationTransfer& tr, const CoarseModel& model, const CoarseCopies& copies,
                    const std::vector<std::pair<std::uint32_t, double>>& leaves, int piece, const glm::dvec3& x) {
  const std::size_t first = tr.terms.size();
  double total = 0.0;
  for (const auto& [leaf, w] : leaves) {
    const std::uint32_t m = copy_of(copies, leaf, piece);
    if (m == UINT32_MAX) continue;
    tr.terms.push_back({find_anchor(tr, m, piece), w, x - model.vertices[m]});
    total += w;
  }
  if (!(total > 1e-9)) {
    tr.terms.resize(first);
    return false;
  }
  for (std::size_t i = first; i < tr.terms.size(); ++i) tr.terms[i].weight /= total;
  return true;
}

double rest_diagonal(const CoarseModel& model) {
  Aabb box;
  for (const glm::dvec3& v : model.vertices) box.expand(v);
  return model.vertices.empty() ? 0.0 : glm::length(box.hi - box.lo);
}

}  // namespace

AnimationTransfer build_transfer(const CoarseModel& model, const CoarseAnimation& animation, const RefinementTree& tree,
                                 const PieceSet& pieces, const AnimateOptions& options) {
  check_inputs(model, animation, tree, pieces);
  AnimationTransfer tr;
  tr.model_vertex_count = model.vertices.size();
  tr.frame_count = animation.frames.size();
  tr.source = !animation.piece_transforms.empty() ? DeformationSource::kRigid
              : !model.tets.empty()               ? DeformationSource::kTets
                                                  : DeformationSource::kSurface;
  tr.layout = make_layout(pieces);
  const CoarseCopies copies = coarse_copies(model);
  const std::vector<std::vector<Tri>> boundary = coarse_boundary(model, copies);
  make_anchors(tr, boundary);
  setup_deformation(tr, model, boundary);
  const PieceBoundaries trees = boundary_trees(tr, model, boundary);
  const auto leaves = all_leaves(tree, pieces.s_vertex_count, model.surface.vertex_count());
  for (std::size_t p = 0; p < tr.layout.vertices.size(); ++p)
    for (std::uint32_t v : tr.layout.vertices[p]) {
      const glm::dvec3 x = pieces.positions[v];
      const std::int64_t origin = pieces.vertex_origin[v];
      if (origin < 0 || !add_leaf_terms(tr, model, copies, leaves[std::size_t(origin)], int(p), x)) {
        if (origin >= 0) ++tr.nearest_fallbacks;
        add_nearest_terms(tr, trees, int(p), x);
      }
      tr.term_offsets.push_back(std::uint32_t(tr.terms.size()));
    }
  setup_fracture(tr, model, animation, pieces, copies, leaves, options.separation_tolerance * rest_diagonal(model));
  return tr;
}

}  // namespace fracref
