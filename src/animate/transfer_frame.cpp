// The anchors' affine maps (step 1) and the evaluation of one frame.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "animate/animate_internal.hpp"
#include "util/error.hpp"

namespace fracref {
namespace animate_detail {
namespace {

// Sumner and Popovic's fourth vertex: the normal scaled so the edge matrix stays well conditioned
// under scaling (1/sqrt of the doubled area).
glm::dmat3 triangle_frame(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 e1 = b - a, e2 = c - a, n = glm::cross(e1, e2);
  const double len = glm::length(n);
  return glm::dmat3(e1, e2, len > 0.0 ? n / std::sqrt(len) : glm::dvec3(0.0));
}

glm::dmat3 tet_frame(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  return glm::dmat3(b - a, c - a, d - a);
}

// Per model vertex, the elements using it (CSR, elements ascending).
void vertex_elements(const std::vector<glm::uvec4>& elements, int corners, std::size_t vertex_count,
                     std::vector<std::uint32_t>& offsets, std::vector<std::uint32_t>& items) {
  offsets.assign(vertex_count + 1, 0);
  for (const glm::uvec4& e : elements)
    for (int k = 0; k < corners; ++k) ++offsets[e[k] + 1];
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  items.assign(offsets.back(), 0);
  std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (std::uint32_t i = 0; i < elements.size(); ++i)
    for (int k = 0; k < corners; ++k) items[fill[elements[i][k]]++] = i;
}

}  // namespace

void setup_deformation(AnimationTransfer& tr, const CoarseModel& model, const std::vector<std::vector<Tri>>& boundary) {
  tr.anchor_element_offsets.assign(tr.anchors.size() + 1, 0);
  if (tr.source == DeformationSource::kRigid) return;
  std::vector<int> element_piece;
  const bool tets = tr.source == DeformationSource::kTets;
  if (tets) {
    tr.elements = model.tets;
    element_piece = model.tet_piece;
  } else {
    for (std::size_t p = 0; p < boundary.size(); ++p)
      for (const Tri& t : boundary[p]) tr.elements.emplace_back(t[0], t[1], t[2], 0u), element_piece.push_back(int(p));
  }
  const std::vector<glm::dvec3>& X = model.vertices;
  for (const glm::uvec4& e : tr.elements) {
    const glm::dmat3 D = tets ? tet_frame(X[e.x], X[e.y], X[e.z], X[e.w]) : triangle_frame(X[e.x], X[e.y], X[e.z]);
    const double det = glm::determinant(D);
    tr.rest_inverse.push_back(std::isfinite(det) && det != 0.0 ? glm::inverse(D) : glm::dmat3(0.0));
  }
  std::vector<std::uint32_t> offsets, items;
  vertex_elements(tr.elements, tets ? 4 : 3, model.vertices.size(), offsets, items);
  tr.anchor_elements.clear();
  for (std::size_t a = 0; a < tr.anchors.size(); ++a) {
    const std::uint32_t m = tr.anchors[a].x;
    const int p = int(tr.anchors[a].y);
    const std::size_t first = tr.anchor_elements.size();
    for (std::uint32_t i = offsets[m]; i < offsets[m + 1]; ++i)
      if (element_piece[items[i]] == p && tr.rest_inverse[items[i]] != glm::dmat3(0.0))
        tr.anchor_elements.push_back(items[i]);
    if (tets && tr.anchor_elements.size() == first)  // the piece has no tet here: use every tet at m
      for (std::uint32_t i = offsets[m]; i < offsets[m + 1]; ++i)
        if (tr.rest_inverse[items[i]] != glm::dmat3(0.0)) tr.anchor_elements.push_back(items[i]);
    if (tr.anchor_elements.size() == first) ++tr.identity_anchors;
    tr.anchor_element_offsets[a + 1] = std::uint32_t(tr.anchor_elements.size());
  }
}

}  // namespace animate_detail

namespace {

using namespace animate_detail;

std::vector<glm::dmat3> anchor_maps(const AnimationTransfer& tr, const CoarseAnimation& animation, std::size_t frame) {
  std::vector<glm::dmat3> A(tr.anchors.size(), glm::dmat3(1.0));
  if (tr.source == DeformationSource::kRigid) {
    for (std::size_t a = 0; a < tr.anchors.size(); ++a) A[a] = glm::dmat3(animation.piece_transforms[frame][tr.anchors[a].y]);
    return A;
  }
  const std::vector<glm::dvec3>& x = animation.frames[frame];
  const bool tets = tr.source == DeformationSource::kTets;
  std::vector<glm::dmat3> F(tr.elements.size());
  for (std::size_t i = 0; i < tr.elements.size(); ++i) {
    const glm::uvec4 e = tr.elements[i];
    const glm::dmat3 D = tets ? tet_frame(x[e.x], x[e.y], x[e.z], x[e.w]) : triangle_frame(x[e.x], x[e.y], x[e.z]);
    F[i] = D * tr.rest_inverse[i];
  }
  for (std::size_t a = 0; a < tr.anchors.size(); ++a) {
    const std::uint32_t begin = tr.anchor_element_offsets[a], end = tr.anchor_element_offsets[a + 1];
    if (begin == end) continue;
    glm::dmat3 sum(0.0);
    for (std::uint32_t i = begin; i < end; ++i) sum += F[tr.anchor_elements[i]];
    A[a] = sum / double(end - begin);
  }
  return A;
}

// Pieces of a shared vertex that have not separated by `frame` take their mean position.
void join_unfractured(const AnimationTransfer& tr, std::size_t frame, std::vector<glm::dvec3>& out) {
  for (const SharedVertex& sv : tr.shared) {
    const std::size_t n = sv.pieces.size();
    std::vector<std::size_t> root(n);
    std::iota(root.begin(), root.end(), std::size_t(0));
    auto find = [&](std::size_t i) {
      while (root[i] != i) i = root[i] = root[root[i]];
      return i;
    };
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        if (sv.pair_fracture[pair_index(i, j, n)] > std::int64_t(frame)) root[find(j)] = find(i);
    for (std::size_t i = 0; i < n; ++i) {
      if (find(i) != i) continue;
      glm::dvec3 sum(0.0);
      std::size_t count = 0;
      for (std::size_t j = 0; j < n; ++j)
        if (find(j) == i) sum += out[sv.slots[j]], ++count;
      if (count < 2) continue;
      const glm::dvec3 mean = sum / double(count);
      for (std::size_t j = 0; j < n; ++j)
        if (find(j) == i) out[sv.slots[j]] = mean;
    }
  }
}

}  // namespace

std::vector<glm::dvec3> transfer_frame(const AnimationTransfer& tr, const CoarseAnimation& animation, std::size_t frame) {
  if (frame >= tr.frame_count || frame >= animation.frames.size())
    throw RunError("animate: frame " + std::to_string(frame) + " out of range (" + std::to_string(tr.frame_count) + " frames)");
  const std::vector<glm::dmat3> A = anchor_maps(tr, animation, frame);
  const std::vector<glm::dvec3>& x = animation.frames[frame];
  std::vector<glm::dvec3> out(tr.layout.slot_count(), glm::dvec3(0.0));
  for (std::size_t slot = 0; slot < out.size(); ++slot) {
    glm::dvec3 sum(0.0);
    for (std::uint32_t i = tr.term_offsets[slot]; i < tr.term_offsets[slot + 1]; ++i) {
      const TransferTerm& t = tr.terms[i];
      sum += t.weight * (A[t.anchor] * t.offset + x[tr.anchors[t.anchor].x]);
    }
    out[slot] = sum;
  }
  join_unfractured(tr, frame, out);
  return out;
}

}  // namespace fracref
