#include "geom/face_guard.hpp"

#include <algorithm>
#include <utility>

#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

// Built for a handful of queries on a whole surface: the build, not the queries, is the cost.
Bvh face_tree(const std::vector<Aabb>& boxes, int threads) {
  BvhOptions o;
  o.threads = threads;
  return build_bvh(boxes, o);
}

}  // namespace

FaceGuard::FaceGuard(std::vector<glm::dvec3> positions, std::vector<TriangleIds> faces, int threads)
    : x_(std::move(positions)), faces_(std::move(faces)), s_faces_(faces_.size()), gone_(faces_.size(), 0) {
  std::vector<Aabb> boxes;
  boxes.reserve(faces_.size());
  for (const TriangleIds& t : faces_) boxes.push_back(box_of(t));
  bvh_ = face_tree(boxes, threads);
}

namespace {

bool box_inside(const Aabb& inner, const Aabb& outer) {
  return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
         inner.hi.x <= outer.hi.x && inner.hi.y <= outer.hi.y && inner.hi.z <= outer.hi.z;
}

}  // namespace

FaceGuard::FaceGuard(std::vector<glm::dvec3> positions, std::vector<TriangleIds> faces, const std::vector<Aabb>& regions,
                     int threads)
    : x_(std::move(positions)),
      faces_(std::move(faces)),
      s_faces_(faces_.size()),
      gone_(faces_.size(), 0),
      restricted_(true),
      regions_(regions),
      region_tree_(build_bvh(regions_)) {
  const std::size_t chunks = chunk_count(faces_.size(), 8192);
  std::vector<std::vector<std::uint32_t>> parts(chunks);
  parallel_chunks(faces_.size(), chunks, threads, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
      if (any_box(region_tree_, box_of(faces_[f]))) parts[c].push_back(std::uint32_t(f));
  });
  std::vector<Aabb> boxes;
  for (const auto& part : parts)
    for (std::uint32_t f : part) {
      indexed_.push_back(f);
      boxes.push_back(box_of(faces_[f]));
    }
  bvh_ = face_tree(boxes, threads);
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

FaceGuard::NewShapes FaceGuard::shapes_of(const std::vector<TriangleIds>& faces) const {
  NewShapes out;
  for (const TriangleIds& t : faces) {
    out.boxes.push_back(box_of(t));
    const glm::dvec3 a = x_[t[0]], b = x_[t[1]], c = x_[t[2]];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    out.prisms.emplace_back();
    if (glm::length(n) > 0.0) out.prisms.back().emplace(std::array<glm::dvec3, 4>{a, b, c, c}, n);
  }
  return out;
}

// Every point of the new faces is within `reach` of a replaced face F, so a face g that the
// prism around F grown by `reach` separates from it, for every F, cannot meet them.
FaceGuard::Slabs FaceGuard::slabs(const std::vector<std::uint32_t>& replaced, double reach) const {
  Slabs out;
  if (reach < 0.0 || replaced.empty()) return out;
  for (std::uint32_t f : replaced) {
    const glm::dvec3 a = x_[faces_[f][0]], b = x_[faces_[f][1]], c = x_[faces_[f][2]];
    const glm::dvec3 n = glm::cross(b - a, c - a);
    if (!(glm::length(n) > 0.0)) return {};  // a degenerate face has no prism: test everything
    out.emplace_back(std::array<glm::dvec3, 4>{a, b, c, c}, n, reach);
  }
  return out;
}

bool FaceGuard::beyond(const Slabs& slabs, const TriangleIds& g) const {
  for (const QuadPrism& p : slabs)
    if (!p.separates({x_[g[0]], x_[g[1]], x_[g[2]]}, {-1, -1, -1})) return false;
  return true;
}

// The near faces come from the box of all the new faces together, which on a long rim chord
// holds a thousand faces of S: each new face's own box rules out most of them before the exact
// test (faces whose boxes miss cannot meet, not even at a shared corner), and so do the slabs.
bool FaceGuard::meets(const std::vector<TriangleIds>& faces, const NewShapes& shapes, std::uint32_t g,
                      const Slabs& near) const {
  const TriangleIds& other = faces_[g];
  const Aabb box = box_of(other);
  bool tested = near.empty();
  for (std::size_t k = 0; k < faces.size(); ++k) {
    if (!shapes.boxes[k].overlaps(box)) continue;
    if (!tested && beyond(near, other)) return false;
    tested = true;
    if (const auto& prism = shapes.prisms[k]) {
      std::array<int, 3> shared{-1, -1, -1};
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c)
          if (other[i] == faces[k][c]) shared[i] = c;
      if (prism->separates({x_[other[0]], x_[other[1]], x_[other[2]]}, shared)) continue;
    }
    if (mesh_faces_intersect(x_, faces[k], other)) return true;
  }
  return false;
}

std::vector<std::uint32_t> FaceGuard::snapshot_near(const std::vector<TriangleIds>& faces,
                                                    const std::vector<std::uint32_t>& replaced,
                                                    const Slabs& near) const {
  Aabb box;
  for (const TriangleIds& t : faces) box.expand(box_of(t));
  std::vector<std::uint32_t> hits;
  if (restricted_) {
    query_box(region_tree_, box, hits);
    if (std::none_of(hits.begin(), hits.end(), [&](std::uint32_t r) { return box_inside(box, regions_[r]); }))
      throw RunError("face guard: new faces outside every region given to it (an internal error; please report it)");
    hits.clear();
  }
  // A long rim chord's new faces span a box of a thousand faces, a few dozen of them near the
  // faces they replace: the prisms skip the rest by subtree.
  if (near.empty()) {
    query_box(bvh_, box, hits);
  } else {
    query_box_where(
        bvh_, box,
        [&](const Aabb& b) {
          return std::all_of(near.begin(), near.end(), [&](const QuadPrism& p) { return p.separates_box(b.lo, b.hi); });
        },
        hits);
  }
  if (restricted_)
    for (std::uint32_t& g : hits) g = indexed_[g];
  std::erase_if(hits, [&](std::uint32_t g) { return std::find(replaced.begin(), replaced.end(), g) != replaced.end(); });
  return hits;
}

bool FaceGuard::meets_snapshot(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced,
                               const Slabs& near) const {
  const NewShapes shapes = shapes_of(faces);
  for (std::uint32_t g : snapshot_near(faces, replaced, near)) {
    if (gone_[g]) continue;
    if (meets(faces, shapes, g, near)) return true;
  }
  return false;
}

std::uint32_t FaceGuard::first_snapshot_hit(const std::vector<TriangleIds>& faces,
                                            const std::vector<std::uint32_t>& replaced, double reach) const {
  const NewShapes shapes = shapes_of(faces);
  const Slabs near = slabs(replaced, reach);
  for (std::uint32_t g : snapshot_near(faces, replaced, near))
    if (meets(faces, shapes, g, near)) return g;
  return kNoHit;
}

bool FaceGuard::clear_given(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced,
                            std::uint32_t hit, double reach) const {
  if (hit != kNoHit && !gone_[hit]) return false;
  const Slabs near = slabs(replaced, reach);
  if (hit != kNoHit && meets_snapshot(faces, replaced, near)) return false;
  return clear_of_accepted(faces, near);
}

bool FaceGuard::clear(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced,
                      double reach) const {
  const Slabs near = slabs(replaced, reach);
  return !meets_snapshot(faces, replaced, near) && clear_of_accepted(faces, near);
}

bool FaceGuard::clear_of_accepted(const std::vector<TriangleIds>& faces, const Slabs& near) const {
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
  const NewShapes shapes = shapes_of(faces);
  for (std::uint32_t k : hits)
    if (meets(faces, shapes, std::uint32_t(s_faces_ + k), near)) return false;
  return true;
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
