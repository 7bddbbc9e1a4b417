#include "geom/face_guard.hpp"

#include <algorithm>
#include <utility>

#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {

// Built for a handful of queries on a surface of up to ~200K faces: the build is the cost.
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
    std::vector<std::uint32_t> hits;
    for (std::size_t f = begin; f < end; ++f) {
      hits.clear();
      query_box(region_tree_, box_of(faces_[f]), hits);
      if (!hits.empty()) parts[c].push_back(std::uint32_t(f));
    }
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

bool FaceGuard::meets_snapshot(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced) const {
  Aabb box;
  for (const TriangleIds& t : faces) box.expand(box_of(t));
  std::vector<std::uint32_t> hits;
  if (restricted_) {
    query_box(region_tree_, box, hits);
    if (std::none_of(hits.begin(), hits.end(), [&](std::uint32_t r) { return box_inside(box, regions_[r]); }))
      throw RunError("face guard: new faces outside every region given to it (an internal error; please report it)");
    hits.clear();
  }
  query_box(bvh_, box, hits);
  if (restricted_)
    for (std::uint32_t& g : hits) g = indexed_[g];
  for (std::uint32_t g : hits) {
    if (gone_[g] || std::find(replaced.begin(), replaced.end(), g) != replaced.end()) continue;
    if (std::any_of(faces.begin(), faces.end(), [&](const TriangleIds& t) { return mesh_faces_intersect(x_, t, faces_[g]); }))
      return true;
  }
  return false;
}

bool FaceGuard::clear(const std::vector<TriangleIds>& faces, const std::vector<std::uint32_t>& replaced) const {
  return !meets_snapshot(faces, replaced) && clear_of_accepted(faces);
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
