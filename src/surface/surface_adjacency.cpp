// Vertex-face CSR, the edge table, vertex flags and per-piece copies of the fracture surface.
#include <algorithm>
#include <numeric>
#include <span>

#include "surface/surface_internal.hpp"
#include "util/counting_sort.hpp"
#include "util/parallel.hpp"

namespace fracref::surface_detail {

namespace {

// Below this many faces a second thread costs more than it saves.
constexpr std::size_t kParallelFaces = 8192;
constexpr int kThreads = 2;

std::size_t parts_for(std::size_t faces) { return faces < kParallelFaces ? 1 : kThreads; }

}  // namespace

void build_vertex_faces(FractureSurface& s) {
  s.vf_faces.resize(3 * s.faces.size());
  // Faces are placed in ascending order, so every vertex's list comes out ascending.
  s.vf_offsets = counting_sort(
      s.faces.size(), s.positions.size(), parts_for(s.faces.size()),
      [&](std::size_t f, auto&& emit) {
        for (std::uint32_t i = 0; i < 3; ++i) emit(s.faces[f][i], i);
      },
      [&](std::size_t f, std::uint32_t, std::uint32_t pos) { s.vf_faces[pos] = std::uint32_t(f); });
}

void build_edges(FractureSurface& s) {
  const std::size_t nv = s.positions.size(), nf = s.faces.size();
  // Bucket the 3F face slots by their edge's smaller vertex, then sort each small bucket by
  // (larger vertex, slot): edges come out sorted and each edge's faces ascending, in O(n). The
  // buckets are sorted and emitted by ranges of vertices side by side: a first pass counts each
  // range's edges, a second writes them where the ranges before them end.
  std::vector<std::uint64_t> slots(3 * nf);
  const std::vector<std::uint32_t> bucket = counting_sort(
      nf, nv, parts_for(nf),
      [&](std::size_t f, auto&& emit) {
        for (std::uint32_t i = 0; i < 3; ++i) emit(std::min(s.faces[f][i], s.faces[f][(i + 1) % 3]), i);
      },
      [&](std::size_t f, std::uint32_t i, std::uint32_t pos) {
        const std::uint32_t a = s.faces[f][i], b = s.faces[f][(i + 1) % 3];
        slots[pos] = (std::uint64_t(std::max(a, b)) << 32) | (3 * std::uint32_t(f) + i);
      });
  const std::size_t chunks = nf < kParallelFaces ? 1 : chunk_count(nv, 2048);
  std::vector<std::uint32_t> first_edge(chunks + 1, 0);
  auto new_edge = [&](std::uint32_t k, std::uint32_t a) {
    return k == bucket[a] || std::uint32_t(slots[k - 1] >> 32) != std::uint32_t(slots[k] >> 32);
  };
  parallel_chunks(nv, chunks, kThreads, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (auto a = std::uint32_t(begin); a < end; ++a) {
      std::sort(slots.begin() + bucket[a], slots.begin() + bucket[a + 1]);
      for (std::uint32_t k = bucket[a]; k < bucket[a + 1]; ++k) first_edge[c + 1] += new_edge(k, a) ? 1 : 0;
    }
  });
  std::partial_sum(first_edge.begin(), first_edge.end(), first_edge.begin());
  s.edges.resize(first_edge.back());
  s.ef_offsets.resize(first_edge.back() + 1);
  s.ef_offsets.back() = std::uint32_t(3 * nf);
  s.ef_faces.resize(3 * nf);
  s.face_edges.resize(3 * nf);
  parallel_chunks(nv, chunks, kThreads, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::uint32_t e = first_edge[c];
    for (auto a = std::uint32_t(begin); a < end; ++a)
      for (std::uint32_t k = bucket[a]; k < bucket[a + 1]; ++k) {
        const auto b = std::uint32_t(slots[k] >> 32), slot = std::uint32_t(slots[k]);
        if (new_edge(k, a)) s.edges[e] = glm::uvec2(a, b), s.ef_offsets[e++] = k;
        s.ef_faces[k] = slot / 3;
        s.face_edges[slot] = e - 1;
      }
  });
  s.edge_special.resize(s.edges.size());
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    const std::uint32_t n = s.ef_offsets[e + 1] - s.ef_offsets[e];
    s.edge_special[e] = n == 1 ? kEdgeBoundary : n == 2 ? kEdgeRegular : kEdgeNonManifold;
  }
}

namespace {

// fan_count for a vertex with at most kSmallFan faces: the faces joined by the edges they share at
// v, pairwise (n² tiny comparisons beat sorting and allocating for the usual 4 to 8 faces).
constexpr std::uint32_t kSmallFan = 16;

std::uint32_t small_fan_count(const FractureSurface& s, std::uint32_t v, std::uint32_t begin, std::uint32_t n) {
  std::uint32_t edge[kSmallFan][2], parent[kSmallFan];
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t f = s.vf_faces[begin + k];
    const std::uint32_t i = s.faces[f].x == v ? 0u : s.faces[f].y == v ? 1u : 2u;
    edge[k][0] = s.face_edges[3 * f + i];
    edge[k][1] = s.face_edges[3 * f + (i + 2) % 3];
    parent[k] = k;
  }
  auto root = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::uint32_t fans = n;
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = a + 1; b < n; ++b) {
      const bool share = edge[a][0] == edge[b][0] || edge[a][0] == edge[b][1] || edge[a][1] == edge[b][0] ||
                         edge[a][1] == edge[b][1];
      if (!share) continue;
      const std::uint32_t ra = root(a), rb = root(b);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb), --fans;
    }
  return fans;
}

}  // namespace

std::uint32_t fan_count(const FractureSurface& s, std::uint32_t v, std::vector<glm::uvec2>& scratch) {
  const std::uint32_t begin = s.vf_offsets[v], n = s.vf_offsets[v + 1] - begin;
  if (n <= 1) return n;
  if (n <= kSmallFan) return small_fan_count(s, v, begin, n);
  // (edge, local face) for the two edges of each incident face that touch v.
  scratch.clear();
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t f = s.vf_faces[begin + k];
    for (std::uint32_t i = 0; i < 3; ++i)
      if (s.faces[f][i] == v) {
        scratch.emplace_back(s.face_edges[3 * f + i], k);
        scratch.emplace_back(s.face_edges[3 * f + (i + 2) % 3], k);
      }
  }
  std::sort(scratch.begin(), scratch.end(), [](glm::uvec2 x, glm::uvec2 y) {
    return x.x != y.x ? x.x < y.x : x.y < y.y;
  });
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::uint32_t fans = n;
  for (std::size_t k = 1; k < scratch.size(); ++k) {
    if (scratch[k].x != scratch[k - 1].x) continue;
    const std::uint32_t ra = root(scratch[k].y), rb = root(scratch[k - 1].y);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb), --fans;
  }
  return fans;
}

namespace {

// The flag an edge of this kind gives both its ends.
std::uint32_t end_flag(std::uint8_t special) {
  return special == kEdgeBoundary ? kVertexBoundary : special == kEdgeNonManifold ? kVertexNonManifold : 0u;
}

}  // namespace

void build_vertex_flags(FractureSurface& s) {
  s.vertex_flags.resize(s.positions.size(), 0);
  for (std::uint32_t& f : s.vertex_flags) f &= kVertexOriginal;
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    s.vertex_flags[s.edges[e].x] |= end_flag(s.edge_special[e]);
    s.vertex_flags[s.edges[e].y] |= end_flag(s.edge_special[e]);
  }
  std::vector<glm::uvec2> scratch;
  for (std::uint32_t v = 0; v < s.positions.size(); ++v)
    if (!(s.vertex_flags[v] & kVertexNonManifold) && fan_count(s, v, scratch) > 1)
      s.vertex_flags[v] |= kVertexNonManifold;
}

// The copies of vertex v (its pieces, ascending), appended to s.copies.
void append_copies(FractureSurface& s, std::uint32_t v, std::vector<std::uint32_t>& pieces) {
  pieces.clear();
  for (std::uint32_t k = s.vf_offsets[v]; k < s.vf_offsets[v + 1]; ++k) {
    const glm::ivec2 p = s.face_pieces[s.vf_faces[k]];
    pieces.push_back(std::uint32_t(p.x));
    pieces.push_back(std::uint32_t(p.y));
  }
  std::sort(pieces.begin(), pieces.end());
  pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());
  for (std::uint32_t p : pieces) s.copies.emplace_back(p, s.piece_vertex_counts[p]++);
}

void build_copies(FractureSurface& s) {
  const std::size_t nv = s.positions.size();
  s.copy_offsets.assign(nv + 1, 0);
  s.copies.clear();
  s.piece_vertex_counts.assign(std::size_t(std::max(s.piece_count, 0)), 0);
  std::vector<std::uint32_t> pieces;
  // Vertices are visited in ascending order, so each piece numbers its vertices ascending.
  for (std::uint32_t v = 0; v < nv; ++v) {
    append_copies(s, v, pieces);
    s.copy_offsets[v + 1] = std::uint32_t(s.copies.size());
  }
}

void extend_after_splits(FractureSurface& s, std::size_t first_vertex, std::size_t first_face,
                         std::span<const std::uint32_t> origin) {
  // A new vertex lies inside a face or an edge: one fan, flagged by the special edges it is on.
  s.vertex_flags.resize(s.positions.size(), 0);
  for (std::size_t v = first_vertex; v < s.positions.size(); ++v) s.vertex_flags[v] = 0;
  for (std::size_t e = 0; e < s.edges.size(); ++e)
    for (std::uint32_t v : {s.edges[e].x, s.edges[e].y})
      if (v >= first_vertex) s.vertex_flags[v] |= end_flag(s.edge_special[e]);
  // A new face is wound as the face it was split from: its sides are in that face's components,
  // whose lowest sides (which number them) are older than it.
  s.side_component.resize(2 * s.faces.size());
  for (std::size_t f = first_face; f < s.faces.size(); ++f) {
    const std::uint32_t o = origin[f - first_face];
    s.side_component[2 * f] = s.side_component[2 * o];
    s.side_component[2 * f + 1] = s.side_component[2 * o + 1];
  }
  // Old vertices keep their pieces (a new face's old corners were its origin's); new vertices
  // come last in every piece's numbering.
  s.copy_offsets.resize(first_vertex + 1);
  s.copies.resize(s.copy_offsets.back());
  s.piece_vertex_counts.assign(std::size_t(std::max(s.piece_count, 0)), 0);
  for (const auto& c : s.copies) ++s.piece_vertex_counts[c.x];
  std::vector<std::uint32_t> pieces;
  for (auto v = std::uint32_t(first_vertex); v < s.positions.size(); ++v) {
    append_copies(s, v, pieces);
    s.copy_offsets.push_back(std::uint32_t(s.copies.size()));
  }
}

}  // namespace fracref::surface_detail
