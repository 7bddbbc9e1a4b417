// Pieces that nearly conform, fitted on a tet lattice of the exterior: labels by the largest
// generalized winding number (the nearest piece in a gap), cleaned up (fit_labels.hpp), S the
// label boundary (build_tet_model()).
#include "coarse/pieces_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "coarse/coarse_internal.hpp"
#include "coarse/fit_labels.hpp"
#include "coarse/tet_lattice.hpp"
#include "geom/bvh.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {
using namespace coarse_detail;

// Each piece's tree and box (for the winding numbers), and one tree over every piece's
// triangles with each triangle's piece (for the nearest piece in a gap).
struct PieceTrees {
  std::vector<Bvh> piece;
  std::vector<Aabb> box;
  Bvh all;
  std::vector<int> all_piece;
};

PieceTrees piece_trees(const std::vector<PieceInput>& pieces) {
  PieceTrees t;
  std::vector<glm::dvec3> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    t.piece.push_back(build_bvh(pieces[p].positions, pieces[p].triangles));
    Aabb box;
    for (const auto& tri : pieces[p].triangles)
      for (std::uint32_t v : tri) box.expand(pieces[p].positions[v]);
    t.box.push_back(box);
    const auto base = std::uint32_t(positions.size());
    positions.insert(positions.end(), pieces[p].positions.begin(), pieces[p].positions.end());
    for (const auto& tri : pieces[p].triangles) triangles.push_back({tri[0] + base, tri[1] + base, tri[2] + base});
    t.all_piece.insert(t.all_piece.end(), pieces[p].triangles.size(), int(p));
  }
  t.all = build_bvh(positions, triangles);
  return t;
}

double signed_volume(const std::vector<glm::dvec3>& x, const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  double v = 0.0;
  for (const auto& t : triangles) v += glm::dot(x[t[0]], glm::cross(x[t[1]], x[t[2]])) / 6.0;
  return v;
}

enum class Where : std::uint8_t { one, gap, overlap, uncovered };

struct Label {
  int piece = 0;
  Where where = Where::one;
};

// The piece of point c: the largest winding number among the pieces whose box (grown by the
// tolerance) holds c, ties to the lower piece; in no piece (all below 1/2), the nearest piece
// within the tolerance, or `uncovered`.
Label label_point(const PieceTrees& t, const glm::dvec3& c, double tolerance) {
  Label best{-1, Where::one};
  double best_w = -INFINITY;
  int inside = 0;
  for (std::size_t p = 0; p < t.piece.size(); ++p) {
    const Aabb& b = t.box[p];
    if (glm::any(glm::lessThan(c, b.lo - tolerance)) || glm::any(glm::greaterThan(c, b.hi + tolerance))) continue;
    const double w = winding_number(t.piece[p], c);
    inside += w >= 0.5;
    if (w > best_w) best_w = w, best.piece = int(p);
  }
  if (inside >= 2) best.where = Where::overlap;
  if (inside >= 1) return best;
  const ClosestPoint near = closest_point(t.all, c, tolerance * tolerance);
  if (!std::isfinite(near.squared_distance)) return {-1, Where::uncovered};
  return {t.all_piece[near.triangle], Where::gap};
}

glm::dvec3 centroid(const TetSet& set, std::size_t t) {
  const glm::uvec4& k = set.tets[t];
  return 0.25 * (set.positions[k.x] + set.positions[k.y] + set.positions[k.z] + set.positions[k.w]);
}

std::vector<Label> label_tets(const TetSet& set, const PieceTrees& trees, double tolerance) {
  std::vector<Label> labels(set.tets.size());
  parallel_chunks(labels.size(), chunk_count(labels.size(), 64), default_threads(),
                  [&](std::size_t, std::size_t begin, std::size_t end) {
                    for (std::size_t t = begin; t < end; ++t) labels[t] = label_point(trees, centroid(set, t), tolerance);
                  });
  return labels;
}

std::string number_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

// A centre farther than the tolerance from every piece is still a gap when it is not much
// farther from them than from B's surface (a lattice tet near B reaches past it by part of a
// cell, and the pieces' outer faces lie on B): it goes to the nearest piece. Otherwise throws,
// for the first such tet (lowest index).
void resolve_uncovered(const TetSet& set, std::vector<Label>& labels, const PieceTrees& trees, const Bvh& exterior,
                       const std::string& file, const FitOptions& o, double diagonal) {
  for (std::size_t t = 0; t < labels.size(); ++t) {
    if (labels[t].where != Where::uncovered) continue;
    const glm::dvec3 c = centroid(set, t);
    const ClosestPoint near = closest_point(trees.all, c);
    const double d = std::sqrt(near.squared_distance), outside = std::sqrt(closest_point(exterior, c).squared_distance);
    if (d <= o.tolerance * diagonal + outside) {
      labels[t] = {trees.all_piece[near.triangle], Where::gap};
      continue;
    }
    throw InputError(file + ": the pieces do not fill the exterior: the point " + point_text(c) +
                     " inside it lies " + number_text(d) + " from the nearest piece, farther than fracture.tolerance (" +
                     number_text(o.tolerance) + " of the diagonal, " + number_text(o.tolerance * diagonal) +
                     "): the pieces leave a wider gap, or were made from another object than the scene's exterior; "
                     "raise fracture.tolerance (at most 0.1) or give the exterior the pieces were cut from");
  }
}

// build_tet_model() names piece i "label i" and the parts of a split label "label i, part k".
void name_pieces(CoarseModel& m, const std::vector<PieceInput>& pieces) {
  for (std::string& name : m.piece_names) {
    if (name.rfind("label ", 0) != 0) continue;
    const std::size_t end = name.find(',');
    const std::size_t label = std::stoul(name.substr(6, end == std::string::npos ? std::string::npos : end - 6));
    if (label < pieces.size()) name = pieces[label].name + (end == std::string::npos ? "" : name.substr(end));
  }
}

// The tet piece p takes when it got none: near its box, whose label keeps other tets; first one
// deep inside one label (deep_in_one_label), then inside p or nearest it (ties to the lowest tet).
std::int64_t nearest_tet(const TetSet& set, const std::vector<bool>& deep, const PieceTrees& trees, std::size_t p,
                         const std::vector<int>& label, const std::vector<std::size_t>& count, double cell) {
  std::int64_t best = -1;
  std::pair<bool, double> best_key{true, INFINITY};
  for (std::size_t t = 0; t < set.tets.size(); ++t) {
    const glm::dvec3 c = centroid(set, t);
    const Aabb& b = trees.box[p];
    if (glm::any(glm::lessThan(c, b.lo - cell)) || glm::any(glm::greaterThan(c, b.hi + cell)) || count[label[t]] < 2) continue;
    const double d = winding_number(trees.piece[p], c) >= 0.5 ? 0.0 : closest_point(trees.piece[p], c).squared_distance;
    if (std::make_pair(!deep[t], d) < best_key) best_key = {!deep[t], d}, best = std::int64_t(t);
  }
  return best;
}

// Every piece holds a tet: one thinner than the cell takes the tet nearest it (named in
// fit.grown). When a tet had to be taken where pieces meet, the fans are cleaned again, and a
// piece that loses its tet to that is an error.
void grow_empty_pieces(const TetSet& set, const PieceTrees& trees, const std::vector<PieceInput>& pieces,
                       std::vector<int>& label, PiecesFit& fit) {
  std::vector<std::size_t> count(pieces.size(), 0);
  for (int l : label) ++count[l];
  bool shallow = false;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    if (count[p] > 0) continue;
    const std::vector<bool> deep = deep_in_one_label(set, label);
    const std::int64_t t = nearest_tet(set, deep, trees, p, label, count, fit.cell);
    if (t < 0)
      throw InputError(pieces[p].file + ": piece '" + pieces[p].name + "' holds no tet of the exterior's lattice (cell " +
                       number_text(fit.cell) + "): it lies outside the exterior");
    shallow = shallow || !deep[t];
    --count[label[t]], ++count[p];
    label[t] = int(p);
    fit.grown.push_back(pieces[p].name);
  }
  if (!shallow) return;
  fit.tets_relabelled += clean_fans(set, label);
  std::fill(count.begin(), count.end(), 0);
  for (int l : label) ++count[l];
  for (std::size_t p = 0; p < pieces.size(); ++p)
    if (count[p] == 0)
      throw InputError(pieces[p].file + ": piece '" + pieces[p].name + "' is thinner than the exterior's lattice cell (" +
                       number_text(fit.cell) + ") where other pieces meet; raise fracture.cells_per_diagonal");
}

void check_exterior(const MeshSoup& exterior, const std::string& file) {
  const double diagonal = bbox_diagonal(exterior.positions);
  if (exterior.triangles.empty() || !std::isfinite(diagonal) || !(diagonal > 0.0))
    throw InputError(file + ": the exterior has no volume to fit the pieces in (no face, or a box of size 0)");
}

TetSet stuff_exterior(const MeshSoup& exterior, const std::string& file, const FitOptions& o) {
  try {
    return stuff_inside(exterior.positions, exterior.triangles, o.cells_per_diagonal, o.warp);
  } catch (const RunError& e) {
    throw InputError(file + ": " + e.what() + " (is the exterior closed and wound outward?)");
  }
}

void measure(PiecesFit& fit, const TetSet& set, const std::vector<Label>& labels, const MeshSoup& exterior,
             const std::vector<PieceInput>& pieces) {
  for (std::size_t t = 0; t < labels.size(); ++t) {
    const double v = tet_volume(set, std::uint32_t(t));
    if (labels[t].where == Where::gap) fit.gap_volume += v;
    if (labels[t].where == Where::overlap) fit.overlap_volume += v;
  }
  for (const PieceInput& p : pieces) fit.pieces_volume += signed_volume(p.positions, p.triangles);
  fit.exterior_volume = signed_volume(exterior.positions, exterior.triangles);
  fit.tets = set.tets.size();
}

// The pieces' labels on one lattice of B, cleaned up but for the pieces that got no tet.
struct Lattice {
  TetSet set;
  InteriorFaces faces;
  std::vector<Label> labels;  // as sampled
  std::vector<int> label;     // cleaned
  std::size_t relabelled = 0;
  std::size_t empty = 0;         // pieces that got no tet
  bool finer_may_help = false;  // one of them has the volume of one of the lattice's tets
};

Lattice label_lattice(const MeshSoup& exterior, const std::string& exterior_file, const Bvh& b, const PieceTrees& trees,
                      const std::vector<double>& volume, const std::string& file, const FitOptions& o, double diagonal) {
  Lattice l;
  l.set = stuff_exterior(exterior, exterior_file, o);
  l.labels = label_tets(l.set, trees, o.tolerance * diagonal);
  resolve_uncovered(l.set, l.labels, trees, b, file, o, diagonal);
  for (const Label& x : l.labels) l.label.push_back(x.piece);
  l.faces = interior_faces(l.set);
  // Cleaning fans may leave strays and merging strays may leave bad fans: in turn while either
  // moves a tet (4 rounds at most), fans last.
  for (int round = 0; round < 4; ++round) {
    const std::size_t notched = relabel_notches(l.set.tets.size(), l.faces, l.label);
    const std::size_t merged = merge_islands(l.set.tets.size(), l.faces, l.label, o.island_fraction);
    const std::size_t cleaned = clean_fans(l.set, l.label);
    l.relabelled += notched + merged + cleaned;
    if (notched + merged + cleaned == 0) break;
  }
  std::vector<bool> seen(volume.size(), false);
  for (int x : l.label) seen[x] = true;
  const double cell = diagonal / o.cells_per_diagonal;
  for (std::size_t p = 0; p < volume.size(); ++p) {
    l.empty += !seen[p];
    l.finer_may_help = l.finer_may_help || (!seen[p] && volume[p] >= cell * cell * cell / 8.0);
  }
  return l;
}

}  // namespace

CoarseModel fit_pieces_model(const MeshSoup& exterior, const std::string& exterior_file,
                             const std::vector<PieceInput>& pieces, const std::string& reason, const FitOptions& o) {
  if (pieces.empty()) throw InputError("pieces: no piece given");
  const std::string& file = pieces[0].file;
  const double diagonal = bbox_diagonal(exterior.positions);
  const PieceTrees trees = piece_trees(pieces);
  check_exterior(exterior, exterior_file);
  const Bvh b = build_bvh(exterior.positions, exterior.triangles);
  std::vector<double> volume;
  for (const PieceInput& p : pieces) volume.push_back(std::abs(signed_volume(p.positions, p.triangles)));
  FitOptions level = o;
  Lattice l = label_lattice(exterior, exterior_file, b, trees, volume, file, level, diagonal);
  // Finer while it may help and helped the last time; the coarser lattice when it did not.
  while (l.finer_may_help && 2.0 * level.cells_per_diagonal <= o.max_cells_per_diagonal) {
    FitOptions finer = level;
    finer.cells_per_diagonal *= 2.0;
    Lattice f = label_lattice(exterior, exterior_file, b, trees, volume, file, finer, diagonal);
    if (f.empty >= l.empty) break;
    l = std::move(f), level = finer;
  }
  PiecesFit fit;
  fit.cell = diagonal / level.cells_per_diagonal;
  fit.tets_relabelled = l.relabelled;
  grow_empty_pieces(l.set, trees, pieces, l.label, fit);
  TetMesh mesh{file, l.set.positions, l.set.tets, std::vector<std::int64_t>(l.label.begin(), l.label.end()), {}};
  TetModelOptions to;
  to.own_vertices = o.own_vertices;
  CoarseModel m = build_tet_model(mesh, nullptr, to);
  name_pieces(m, pieces);
  m.fit = std::move(fit);
  m.fit.fitted = true;
  m.fit.reason = reason;
  m.fit.tolerance = o.tolerance * diagonal;
  measure(m.fit, l.set, l.labels, exterior, pieces);
  return m;
}

std::int64_t find_hull_gap(const CoarseModel& m, double distance) {
  if (m.hull.empty() || !(distance > 0.0)) return -1;
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (const glm::uvec3& h : m.hull) tris.push_back({h.x, h.y, h.z});
  const Bvh bvh = build_bvh(m.vertices, tris);
  auto normal = [&](std::size_t f) {
    const glm::dvec3 n = glm::cross(m.vertices[tris[f][1]] - m.vertices[tris[f][0]], m.vertices[tris[f][2]] - m.vertices[tris[f][0]]);
    const double l = glm::length(n);
    return l > 0.0 ? n / l : n;
  };
  std::vector<std::uint32_t> near;
  for (std::size_t f = 0; f < tris.size(); ++f) {
    const glm::dvec3 c = (m.vertices[tris[f][0]] + m.vertices[tris[f][1]] + m.vertices[tris[f][2]]) / 3.0;
    Aabb box{c - distance, c + distance};
    near.clear();
    query_box(bvh, box, near);
    for (std::uint32_t g : near) {
      if (m.hull_piece[g] == m.hull_piece[f] || glm::dot(normal(f), normal(g)) > -0.9) continue;
      const auto& t = tris[g];
      const ClosestPoint q = closest_point_on_triangle(c, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]);
      if (q.squared_distance <= distance * distance) return std::int64_t(f);
    }
  }
  return -1;
}

CoarseModel build_pieces_or_fit(const MeshSoup& exterior, const std::string& exterior_file,
                                const std::vector<PieceInput>& pieces, const PiecesOptions& exact, const FitOptions& fit) {
  std::string reason;
  try {
    CoarseModel m = build_pieces_model(pieces, exact);
    const double d = fit.tolerance * bbox_diagonal(exterior.positions);
    const std::int64_t gap = m.piece_count > 1 ? find_hull_gap(m, d) : -1;
    if (m.piece_count < 2 || (!m.surface.faces.empty() && gap < 0)) return m;
    reason = m.surface.faces.empty() ? "no face of one piece matches a face of another"
                                     : "face " + std::to_string(gap) + " of the pieces' hull (piece '" +
                                           m.piece_names[m.hull_piece[gap]] + "') faces another piece across a gap";
  } catch (const PiecesMismatch& e) {
    reason = e.what();
  }
  return fit_pieces_model(exterior, exterior_file, pieces, reason, fit);
}

}  // namespace fracref
