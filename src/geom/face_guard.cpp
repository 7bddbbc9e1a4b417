#include "geom/face_guard.hpp"

#include <algorithm>
#include <utility>

#include "geom/bvh_traverse.hpp"
#include "geom/morton.hpp"
#include "geom/parallel.hpp"

namespace fracref {

FaceGuard::FaceGuard(std::vector<glm::dvec3> positions, std::vector<TriangleIds> faces)
    : x_(std::move(positions)), faces_(std::move(faces)), s_faces_(faces_.size()), gone_(faces_.size(), 0) {
  std::vector<Aabb> boxes;
  boxes.reserve(faces_.size());
  for (const TriangleIds& t : faces_) boxes.push_back(box_of(t));
  bvh_ = build_bvh(boxes);
}

std::uint32_t FaceGuard::add_vertex(const glm::dvec3& p) {
  x_.push_back(p);
  return std::uint32_t(x_.size() - 1);
}

Aabb FaceGuard::box_of(const TriangleIds& t) const {
  Aabb box;
  for (std::uint32_t v : t) box.expand(x_[v]);
  return box;
}

void FaceGuard::snapshot_hits(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced,
                              bool skip_gone, bool first_only, std::vector<std::uint32_t>& out) const {
  Aabb box;
  for (const TriangleIds& t : faces) box.expand(box_of(t));
  std::vector<std::uint32_t> hits;
  query_box(bvh_, box, hits);
  for (std::uint32_t g : hits) {
    if ((skip_gone && gone_[g]) || std::find(replaced.begin(), replaced.end(), g) != replaced.end()) continue;
    if (std::none_of(faces.begin(), faces.end(), [&](const TriangleIds& t) { return mesh_faces_intersect(x_, t, faces_[g]); }))
      continue;
    out.push_back(g);
    if (first_only) return;
  }
}

bool FaceGuard::clear(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced) const {
  std::vector<std::uint32_t> hit;
  snapshot_hits(faces, replaced, true, true, hit);
  return hit.empty() && clear_of_accepted(faces);
}

bool FaceGuard::clear_of_accepted(const std::vector<TriangleIds>& faces) const {
  Aabb box;
  for (const TriangleIds& t : faces) box.expand(box_of(t));
  std::vector<std::uint32_t> hits;
  for (const Run& run : runs_) {
    const std::size_t first = hits.size();
    query_box(run.tree, box, hits);
    for (std::size_t k = first; k < hits.size(); ++k) hits[k] += std::uint32_t(run.begin);
  }
  for (std::size_t k = runs_.empty() ? 0 : runs_.back().end; k < new_boxes_.size(); ++k)
    if (new_boxes_[k].overlaps(box)) hits.push_back(std::uint32_t(k));
  for (std::uint32_t k : hits)
    for (const TriangleIds& t : faces)
      if (mesh_faces_intersect(x_, t, faces_[s_faces_ + k])) return false;
  return true;
}

std::vector<std::vector<std::uint32_t>> FaceGuard::snapshot_blockers(const std::vector<std::vector<TriangleIds>>& faces,
                                                                     const std::vector<std::vector<std::uint32_t>>& replaced,
                                                                     int threads) const {
  std::vector<std::vector<std::uint32_t>> out(faces.size());
  // Queries in Z-order: consecutive ones descend the same branches of the tree, still in cache.
  std::vector<glm::dvec3> centres(faces.size(), glm::dvec3(0.0));
  for (std::size_t k = 0; k < faces.size(); ++k)
    if (!faces[k].empty()) centres[k] = box_of(faces[k][0]).lo;
  const std::vector<std::uint32_t> order = morton_order(centres);
  geom_detail::parallel_chunks(faces.size(), geom_detail::chunk_count(faces.size(), 64), threads,
                               [&](std::size_t, std::size_t begin, std::size_t end) {
                                 for (std::size_t i = begin; i < end; ++i) {
                                   const std::uint32_t k = order[i];
                                   snapshot_hits(faces[k], replaced[k], false, false, out[k]);
                                 }
                               });
  return out;
}

std::vector<std::vector<std::uint32_t>> FaceGuard::batch_conflicts(const std::vector<std::vector<TriangleIds>>& faces,
                                                                   int threads) const {
  std::vector<Aabb> boxes(faces.size());
  for (std::size_t k = 0; k < faces.size(); ++k)
    for (const TriangleIds& t : faces[k]) boxes[k].expand(box_of(t));
  BvhOptions o;
  o.threads = threads;
  const Bvh tree = build_bvh(boxes, o);
  using Pair = std::pair<std::uint32_t, std::uint32_t>;
  std::vector<Pair> pairs = collect_overlaps<Pair>(tree, tree, true, threads, [&](std::uint32_t i, std::uint32_t j, std::vector<Pair>& out) {
    for (const TriangleIds& a : faces[i])
      for (const TriangleIds& b : faces[j])
        if (mesh_faces_intersect(x_, a, b)) return out.push_back({j, i});
  });
  std::sort(pairs.begin(), pairs.end());
  std::vector<std::vector<std::uint32_t>> out(faces.size());
  for (const Pair& p : pairs) out[p.first].push_back(p.second);
  return out;
}

void FaceGuard::accept(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced) {
  for (std::uint32_t f : replaced) gone_[f] = 1;
  for (const TriangleIds& t : faces) {
    faces_.push_back(t);
    new_boxes_.push_back(box_of(t));
  }
  index_new_boxes();
}

void FaceGuard::index_new_boxes() {
  constexpr std::size_t kTail = 32;
  const std::size_t indexed = runs_.empty() ? 0 : runs_.back().end;
  if (new_boxes_.size() - indexed < kTail) return;
  auto make_run = [&](std::size_t begin, std::size_t end) {
    Run run{begin, end, {}};
    run.tree = build_bvh(std::vector<Aabb>(new_boxes_.begin() + std::ptrdiff_t(begin), new_boxes_.begin() + std::ptrdiff_t(end)));
    return run;
  };
  runs_.push_back(make_run(indexed, new_boxes_.size()));
  while (runs_.size() >= 2) {
    const Run& last = runs_.back();
    const Run& before = runs_[runs_.size() - 2];
    if (before.end - before.begin > last.end - last.begin) break;
    Run merged = make_run(before.begin, last.end);
    runs_.pop_back();
    runs_.back() = std::move(merged);
  }
}

}  // namespace fracref
