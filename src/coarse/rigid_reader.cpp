// Per-piece rigid transforms applied to the coarse model's rest vertices.
#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "coarse/animation.hpp"
#include "coarse/coarse_internal.hpp"

namespace fracref {
namespace {
using namespace coarse_detail;
namespace fs = std::filesystem;

struct Transform {
  std::int64_t frame = 0;
  int piece = 0;
  double m[12] = {};  // rows of [R | t]
  std::size_t line = 0;
};

void check_rigid(const TokenLines& in, const double (&m)[12]) {
  const glm::dmat3 r(m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]);  // columns
  const glm::dmat3 g = glm::transpose(r) * r;
  double worst = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) worst = std::max(worst, std::abs(g[i][j] - (i == j ? 1.0 : 0.0)));
  if (worst > 1e-4)
    throw in.error("the 3x3 part is not a rotation (R^T R differs from the identity by " + std::to_string(worst) +
                   "; scaling and shear are not rigid)");
  if (glm::determinant(r) <= 0) throw in.error("the 3x3 part is a reflection (determinant < 0), not a rotation");
}

std::vector<Transform> read_transforms(const fs::path& path, int pieces) {
  const std::string text = io_detail::read_whole_file(path);
  TokenLines in(path.string(), text);
  std::vector<Transform> out;
  while (in.next()) {
    in.expect_tokens(14, "transform", "frame piece r00 r01 r02 t0 r10 r11 r12 t1 r20 r21 r22 t2");
    Transform t;
    t.frame = in.integer(in.tokens()[0], "frame");
    const std::int64_t piece = in.integer(in.tokens()[1], "piece");
    if (t.frame < 0 || t.frame > 100000000) throw in.error("frame " + std::to_string(t.frame) + " is out of range [0, 1e8]");
    if (piece < 0 || piece >= pieces)
      throw in.error("piece " + std::to_string(piece) + " is out of range (the model has " + std::to_string(pieces) + " pieces)");
    t.piece = int(piece);
    for (int k = 0; k < 12; ++k) t.m[k] = in.real(in.tokens()[2 + k], "matrix entry");
    check_rigid(in, t.m);
    t.line = in.line();
    out.push_back(t);
  }
  return out;
}

bool transform_less(const Transform* a, const Transform* b) {
  return std::tie(a->frame, a->piece, a->line) < std::tie(b->frame, b->piece, b->line);
}

bool same_key(const Transform* a, const Transform* b) { return a->frame == b->frame && a->piece == b->piece; }

// The repeated pair on the earliest line, in `sorted` (by key, then line): the error names it and
// the line that first gave the pair.
void check_repeats(const std::vector<const Transform*>& sorted, const fs::path& path) {
  const Transform* repeat = nullptr;
  const Transform* first = nullptr;
  for (std::size_t i = 1, group = 0; i < sorted.size(); ++i) {
    if (!same_key(sorted[i], sorted[i - 1])) group = i;
    else if (!repeat || sorted[i]->line < repeat->line) repeat = sorted[i], first = sorted[group];
  }
  if (repeat)
    throw input_error_at(path.string(), repeat->line, "frame " + std::to_string(repeat->frame) + " piece " +
                                                          std::to_string(repeat->piece) + " is already given on line " +
                                                          std::to_string(first->line));
}

// Per (frame, piece) the transform, after checking each pair appears exactly once. The missing
// pair is found on the sorted list before the table is made: a frame number up to 1e8 on one
// line must not allocate a table for 1e8 frames.
std::vector<std::vector<const Transform*>> arrange(const std::vector<Transform>& list, int pieces, const fs::path& path) {
  std::int64_t frames = 0;
  for (const Transform& t : list) frames = std::max(frames, t.frame + 1);
  if (frames == 0) throw InputError(path.string() + ": no transform given");
  std::vector<const Transform*> sorted;
  for (const Transform& t : list) sorted.push_back(&t);
  std::sort(sorted.begin(), sorted.end(), transform_less);
  check_repeats(sorted, path);
  for (std::size_t k = 0;; ++k) {  // pair k is (k / pieces, k % pieces); `sorted` now has no repeat
    if (k < sorted.size() && std::size_t(sorted[k]->frame) * pieces + std::size_t(sorted[k]->piece) == k) continue;
    if (k == std::size_t(frames) * pieces) break;
    throw InputError(path.string() + ": frame " + std::to_string(k / pieces) + " has no transform for piece " +
                     std::to_string(k % pieces) + " (frames run from 0 to " + std::to_string(frames - 1) +
                     ", every piece in every frame)");
  }
  std::vector<std::vector<const Transform*>> grid(std::size_t(frames), std::vector<const Transform*>(pieces, nullptr));
  for (const Transform* t : sorted) grid[std::size_t(t->frame)][t->piece] = t;
  return grid;
}

// (vertex, piece) for every piece that uses a vertex, sorted.
std::vector<std::pair<std::uint32_t, int>> vertex_pieces(const CoarseModel& model) {
  std::vector<std::pair<std::uint32_t, int>> uses;
  for (std::size_t t = 0; t < model.tets.size(); ++t)
    for (int i = 0; i < 4; ++i) uses.emplace_back(model.tets[t][i], model.tet_piece[t]);
  for (std::size_t h = 0; h < model.hull.size(); ++h)
    for (int i = 0; i < 3; ++i) uses.emplace_back(model.hull[h][i], model.hull_piece[h]);
  for (std::size_t c = 0; c < model.surface.copies.size(); ++c)
    uses.emplace_back(model.surface_copy_model_vertex[c], int(model.surface.copies[c].x));
  std::sort(uses.begin(), uses.end());
  uses.erase(std::unique(uses.begin(), uses.end()), uses.end());
  return uses;
}

bool same_transform(const Transform& a, const Transform& b) { return std::equal(a.m, a.m + 12, b.m); }

// Vertices shared by pieces that move differently make the rigid form ambiguous.
void check_shared(const CoarseModel& model, const std::vector<std::pair<std::uint32_t, int>>& uses,
                  const std::vector<std::vector<const Transform*>>& grid, const fs::path& path) {
  std::vector<std::tuple<int, int, std::uint32_t>> pairs;  // (owner, other piece, lowest vertex)
  for (std::size_t i = 1; i < uses.size(); ++i) {
    if (uses[i].first != uses[i - 1].first) continue;
    std::size_t owner = i - 1;
    while (owner > 0 && uses[owner - 1].first == uses[i].first) --owner;
    pairs.emplace_back(uses[owner].second, uses[i].second, uses[i].first);
  }
  std::sort(pairs.begin(), pairs.end());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [p, q, v] = pairs[k];
    if (k > 0 && std::get<0>(pairs[k - 1]) == p && std::get<1>(pairs[k - 1]) == q) continue;
    for (std::size_t f = 0; f < grid.size(); ++f)
      if (!same_transform(*grid[f][p], *grid[f][q]))
        throw input_error_at(path.string(), grid[f][q]->line,
                             "vertex " + std::to_string(v) + " is shared by pieces " + std::to_string(p) + " ('" +
                                 model.piece_names[p] + "') and " + std::to_string(q) + " ('" + model.piece_names[q] +
                                 "'), which move differently in frame " + std::to_string(f) +
                                 "; in the rigid form every piece must own its vertices (duplicate them in the "
                                 "model, or give per-frame positions)");
  }
}

glm::dmat4 to_matrix(const Transform& t) {
  glm::dmat4 m(1.0);
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[c][r] = t.m[4 * r + c];
    m[3][r] = t.m[4 * r + 3];
  }
  return m;
}

}  // namespace

CoarseAnimation load_rigid(const fs::path& transforms, double fps, const CoarseModel& model) {
  if (!(fps > 0) || !std::isfinite(fps)) throw InputError(transforms.string() + ": fps must be a positive number");
  const std::vector<Transform> list = read_transforms(transforms, model.piece_count);
  const auto grid = arrange(list, model.piece_count, transforms);
  const auto uses = vertex_pieces(model);
  check_shared(model, uses, grid, transforms);
  CoarseAnimation anim;
  anim.fps = fps;
  std::vector<int> owner(model.vertices.size(), -1);
  for (auto it = uses.rbegin(); it != uses.rend(); ++it) owner[it->first] = it->second;  // lowest piece wins
  for (const auto& row : grid) {
    std::vector<glm::dmat4> mats;
    for (const Transform* t : row) mats.push_back(to_matrix(*t));
    std::vector<glm::dvec3> frame(model.vertices);
    for (std::size_t v = 0; v < frame.size(); ++v)
      if (owner[v] >= 0) frame[v] = glm::dvec3(mats[owner[v]] * glm::dvec4(model.vertices[v], 1.0));
    anim.frames.push_back(std::move(frame));
    anim.piece_transforms.push_back(std::move(mats));
  }
  return anim;
}

}  // namespace fracref
