// Fracture times (step 4): when the copies of a coarse S vertex separate, per pair of pieces, and
// what that means for every vertex the pieces share.
#include <algorithm>

#include "animate/animate_internal.hpp"

namespace fracref::animate_detail {
namespace {

using Leaves = std::vector<std::vector<std::pair<std::uint32_t, double>>>;

// Per coarse S vertex, the fracture frame of each pair of its copies (pair_index order).
struct CoarsePairs {
  std::vector<std::uint32_t> offsets{0};
  std::vector<std::int64_t> frames;
};

std::int64_t separation_frame(const CoarseAnimation& animation, std::uint32_t a, std::uint32_t b, double tolerance) {
  if (a == b) return kNeverFractures;
  for (std::size_t t = 0; t < animation.frames.size(); ++t)
    if (glm::length(animation.frames[t][a] - animation.frames[t][b]) > tolerance) return std::int64_t(t);
  return kNeverFractures;
}

CoarsePairs coarse_pairs(const CoarseCopies& c, const CoarseAnimation& animation, double tolerance,
                         std::vector<std::int64_t>& first_fracture) {
  CoarsePairs out;
  const std::size_t count = c.offsets.size() - 1;
  first_fracture.assign(count, kNeverFractures);
  for (std::size_t s = 0; s < count; ++s) {
    const std::uint32_t b = c.offsets[s], n = c.offsets[s + 1] - b;
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t j = i + 1; j < n; ++j) {
        const std::int64_t f = separation_frame(animation, c.copies[b + i].y, c.copies[b + j].y, tolerance);
        out.frames.push_back(f);
        first_fracture[s] = std::min(first_fracture[s], f);
      }
    out.offsets.push_back(std::uint32_t(out.frames.size()));
  }
  return out;
}

// Position of `piece` among the copies of coarse vertex s, or -1.
int copy_rank(const CoarseCopies& c, std::uint32_t s, int piece) {
  for (std::uint32_t e = c.offsets[s]; e < c.offsets[s + 1]; ++e)
    if (int(c.copies[e].x) == piece) return int(e - c.offsets[s]);
  return -1;
}

struct Context {
  const CoarseCopies& copies;
  const CoarsePairs& pairs;
  const Leaves& leaves;
};

// Fracture frame of S vertex v between pieces p < q: the minimum over its leaves with both copies.
std::int64_t s_vertex_pair(const Context& cx, std::uint32_t v, int p, int q) {
  std::int64_t best = kUnknownFrame;
  for (const auto& [leaf, w] : cx.leaves[v]) {
    const int i = copy_rank(cx.copies, leaf, p), j = copy_rank(cx.copies, leaf, q);
    if (i < 0 || j < 0) continue;
    const std::size_t n = cx.copies.offsets[leaf + 1] - cx.copies.offsets[leaf];
    const std::int64_t f = cx.pairs.frames[cx.pairs.offsets[leaf] + pair_index(std::size_t(i), std::size_t(j), n)];
    best = best == kUnknownFrame ? f : std::min(best, f);
  }
  return best;
}

std::int64_t min_known(std::int64_t a, std::int64_t b) {
  if (a == kUnknownFrame) return b;
  if (b == kUnknownFrame) return a;
  return std::min(a, b);
}

// The shared vertices with their pieces and slots, pair frames unknown.
std::vector<SharedVertex> shared_vertices(const PieceLayout& layout) {
  std::vector<std::array<std::uint32_t, 3>> uses;  // (vertex, piece, slot)
  for (std::size_t p = 0; p < layout.vertices.size(); ++p)
    for (std::size_t i = 0; i < layout.vertices[p].size(); ++i)
      uses.push_back({layout.vertices[p][i], std::uint32_t(p), layout.offsets[p] + std::uint32_t(i)});
  std::sort(uses.begin(), uses.end());
  std::vector<SharedVertex> out;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j][0] == uses[i][0]) ++j;
    if (j - i >= 2) {
      SharedVertex sv;
      sv.vertex = uses[i][0];
      for (std::size_t k = i; k < j; ++k) sv.pieces.push_back(int(uses[k][1])), sv.slots.push_back(uses[k][2]);
      sv.pair_fracture.assign((j - i) * (j - i - 1) / 2, kUnknownFrame);
      out.push_back(std::move(sv));
    }
    i = j;
  }
  return out;
}

// The pair frame of pieces (p, q) at a neighbouring shared vertex, or unknown.
std::int64_t pair_at(const SharedVertex& sv, int p, int q) {
  auto ip = std::find(sv.pieces.begin(), sv.pieces.end(), p), iq = std::find(sv.pieces.begin(), sv.pieces.end(), q);
  if (ip == sv.pieces.end() || iq == sv.pieces.end()) return kUnknownFrame;
  return sv.pair_fracture[pair_index(std::size_t(ip - sv.pieces.begin()), std::size_t(iq - sv.pieces.begin()), sv.pieces.size())];
}

// Directed edges between shared vertices (indices into `shared`), sorted.
std::vector<std::pair<std::uint32_t, std::uint32_t>> shared_edges(const std::vector<SharedVertex>& shared, const PieceSet& pieces) {
  std::vector<std::int32_t> index(pieces.positions.size(), -1);
  for (std::size_t i = 0; i < shared.size(); ++i) index[shared[i].vertex] = std::int32_t(i);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const PieceSet::Piece& piece : pieces.pieces)
    for (const auto& t : piece.triangles)
      for (int k = 0; k < 3; ++k) {
        const std::int32_t a = index[t[k]], b = index[t[(k + 1) % 3]];
        if (a >= 0 && b >= 0) edges.push_back({std::uint32_t(a), std::uint32_t(b)}), edges.push_back({std::uint32_t(b), std::uint32_t(a)});
      }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// Shared B vertices (on a trace) take, per pair, the minimum over their nearest known neighbours.
void propagate(std::vector<SharedVertex>& shared, const std::vector<bool>& known, const PieceSet& pieces) {
  const auto edges = shared_edges(shared, pieces);
  std::vector<std::uint32_t> layer;
  std::vector<std::int64_t> depth(shared.size(), -1);
  for (std::size_t i = 0; i < shared.size(); ++i)
    if (known[i]) depth[i] = 0, layer.push_back(std::uint32_t(i));
  for (std::int64_t d = 1; !layer.empty(); ++d) {
    std::vector<std::uint32_t> next;
    for (std::uint32_t u : layer)
      for (auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(u, 0u)); it != edges.end() && it->first == u; ++it)
        if (depth[it->second] < 0) depth[it->second] = d, next.push_back(it->second);
    std::sort(next.begin(), next.end());
    for (std::uint32_t v : next) {
      SharedVertex& sv = shared[v];
      const std::size_t n = sv.pieces.size();
      for (auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(v, 0u)); it != edges.end() && it->first == v; ++it) {
        if (depth[it->second] != d - 1) continue;
        for (std::size_t i = 0; i < n; ++i)
          for (std::size_t j = i + 1; j < n; ++j) {
            std::int64_t& f = sv.pair_fracture[pair_index(i, j, n)];
            f = min_known(f, pair_at(shared[it->second], sv.pieces[i], sv.pieces[j]));
          }
      }
    }
    layer = std::move(next);
  }
}

}  // namespace

void setup_fracture(AnimationTransfer& tr, const CoarseModel& model, const CoarseAnimation& animation,
                    const PieceSet& pieces, const CoarseCopies& copies, const Leaves& leaves, double tolerance) {
  const CoarsePairs pairs = coarse_pairs(copies, animation, tolerance, tr.coarse_fracture_frame);
  const Context cx{copies, pairs, leaves};
  tr.shared = shared_vertices(tr.layout);
  std::vector<bool> known(tr.shared.size(), true);
  for (std::size_t k = 0; k < tr.shared.size(); ++k) {
    SharedVertex& sv = tr.shared[k];
    const std::int64_t origin = pieces.vertex_origin[sv.vertex];
    if (origin < 0) {
      known[k] = false;
      continue;
    }
    const std::size_t n = sv.pieces.size();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        sv.pair_fracture[pair_index(i, j, n)] = s_vertex_pair(cx, std::uint32_t(origin), sv.pieces[i], sv.pieces[j]);
  }
  propagate(tr.shared, known, pieces);
  for (SharedVertex& sv : tr.shared)
    for (std::int64_t& f : sv.pair_fracture)
      if (f == kUnknownFrame) f = 0;
}

}  // namespace fracref::animate_detail
