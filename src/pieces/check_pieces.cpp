// check_pieces: every piece closed, edge-manifold, outward and free of self-intersections, and
// the pieces partitioning B (volumes, random inside points).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "geom/bvh.hpp"
#include "geom/intersect.hpp"
#include "pieces/pieces.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using Tri = std::array<std::uint32_t, 3>;

double signed_volume(const std::vector<glm::dvec3>& positions, const std::vector<Tri>& triangles) {
  double sum = 0.0;
  for (const Tri& t : triangles) sum += glm::dot(positions[t[0]], glm::cross(positions[t[1]], positions[t[2]]));
  return sum / 6.0;
}

// The piece on its own vertices (ascending shared index), for the BVH and the exact checks.
struct CompactMesh {
  std::vector<glm::dvec3> positions;
  std::vector<Tri> triangles;
};

CompactMesh compact(const PieceSet& set, const PieceSet::Piece& piece) {
  std::vector<std::uint32_t> used;
  for (const Tri& t : piece.triangles) used.insert(used.end(), t.begin(), t.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  CompactMesh out;
  for (std::uint32_t v : used) out.positions.push_back(set.positions[v]);
  for (const Tri& t : piece.triangles) {
    Tri local;
    for (int k = 0; k < 3; ++k) local[k] = std::uint32_t(std::lower_bound(used.begin(), used.end(), t[k]) - used.begin());
    out.triangles.push_back(local);
  }
  return out;
}

// Counts the edge defects and names the first of each kind.
void check_edges(const std::vector<Tri>& triangles, PieceCheck& check, std::vector<std::string>& why) {
  std::vector<std::array<std::uint32_t, 3>> keyed;  // (min, max, forward)
  for (const Tri& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      keyed.push_back({std::min(a, b), std::max(a, b), a < b ? 1u : 0u});
    }
  std::sort(keyed.begin(), keyed.end());
  std::string open, non_manifold, misoriented;
  for (std::size_t i = 0; i < keyed.size();) {
    std::size_t j = i;
    while (j < keyed.size() && keyed[j][0] == keyed[i][0] && keyed[j][1] == keyed[i][1]) ++j;
    const std::string name = std::to_string(keyed[i][0]) + "-" + std::to_string(keyed[i][1]);
    if (j - i == 1) {
      if (check.open_edges++ == 0) open = name;
    } else if (j - i > 2) {
      if (check.non_manifold_edges++ == 0) non_manifold = name;
    } else if (keyed[i][2] == keyed[i + 1][2]) {
      if (check.misoriented_edges++ == 0) misoriented = name;
    }
    i = j;
  }
  if (check.open_edges) why.push_back("not closed (" + std::to_string(check.open_edges) + " edges with one face, e.g. " + open + ")");
  if (check.non_manifold_edges)
    why.push_back("not edge-manifold (" + std::to_string(check.non_manifold_edges) + " edges with 3 or more faces, e.g. " +
                  non_manifold + ")");
  if (check.misoriented_edges)
    why.push_back("inconsistently oriented (" + std::to_string(check.misoriented_edges) +
                  " edges used twice in one direction, e.g. " + misoriented + ")");
}

// "fracture triangle 12 (S vertices 3, 4, 9) near (x, y, z)" or "exterior triangle ...".
std::string describe(const PieceSet& set, const PieceSet::Piece& piece, std::size_t t, const CompactMesh& mesh) {
  const auto& tri = piece.triangles[t];
  std::string ids;
  for (std::uint32_t v : tri) {
    const std::int64_t o = set.vertex_origin[v];
    ids += (ids.empty() ? "" : ", ") + (o >= 0 ? "S " + std::to_string(o) : "B " + std::to_string(-1 - o));
  }
  const glm::dvec3 c = (mesh.positions[mesh.triangles[t][0]] + mesh.positions[mesh.triangles[t][1]] + mesh.positions[mesh.triangles[t][2]]) / 3.0;
  char at[96];
  std::snprintf(at, sizeof at, "(%.6g, %.6g, %.6g)", c.x, c.y, c.z);
  return std::string(piece.inside[t] ? "fracture" : "exterior") + " triangle " + std::to_string(t) + " (vertices " + ids + ") near " + at;
}

PieceCheck check_piece(const PieceSet& set, std::size_t p, const CompactMesh& mesh, const PieceCheckOptions& options,
                       std::vector<std::string>& failures) {
  const PieceSet::Piece& piece = set.pieces[p];
  PieceCheck check;
  check.triangles = piece.triangles.size();
  check.inside_triangles = std::size_t(std::count(piece.inside.begin(), piece.inside.end(), std::uint8_t(1)));
  std::vector<std::string> why;
  if (piece.triangles.empty()) why.push_back("empty (no triangles)");
  check.volume = signed_volume(mesh.positions, mesh.triangles);
  check_edges(piece.triangles, check, why);
  if (!piece.triangles.empty() && !check.outward()) why.push_back("not outward (volume " + std::to_string(check.volume) + ")");
  try {
    SelfIntersectionOptions so;
    so.max_report = options.max_self_intersections;
    so.threads = std::max(1, options.threads);
    const auto pairs = find_self_intersections(mesh.positions, mesh.triangles, so);
    check.self_intersections = pairs.size();
    if (!pairs.empty())
      why.push_back(std::to_string(pairs.size()) + (pairs.size() >= so.max_report ? " or more" : "") +
                    " pairs of intersecting faces, e.g. " + describe(set, piece, pairs[0].first, mesh) + " and " +
                    describe(set, piece, pairs[0].second, mesh));
  } catch (const InputError& e) {
    why.push_back(std::string("degenerate: ") + e.what());
  }
  for (const std::string& w : why) failures.push_back("piece " + std::to_string(p) + ": " + w);
  return check;
}

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

double unit_random(std::uint64_t& state) { return double(splitmix64(state) >> 11) * 0x1.0p-53; }

void check_points(const std::vector<CompactMesh>& meshes, const Bvh& exterior, const PieceCheckOptions& options,
                  PieceReport& report) {
  std::vector<Bvh> trees;
  for (const CompactMesh& m : meshes) trees.push_back(m.triangles.empty() ? Bvh{} : build_bvh(m.positions, m.triangles));
  Aabb box;
  for (const glm::dvec3& p : exterior.positions) box.expand(p);
  std::uint64_t state = options.seed;
  const std::size_t tries = 200 * options.sample_points + 1000;
  for (std::size_t i = 0; i < tries && report.points_tested < options.sample_points; ++i) {
    const glm::dvec3 r(unit_random(state), unit_random(state), unit_random(state));
    const glm::dvec3 x = box.lo + r * (box.hi - box.lo);
    if (!point_in_mesh(exterior, x)) continue;
    ++report.points_tested;
    std::size_t count = 0;
    for (std::size_t p = 0; p < trees.size(); ++p)
      if (!meshes[p].triangles.empty() && point_in_mesh(trees[p], x)) ++count;
    if (count == 0) ++report.points_in_no_piece;
    if (count > 1) ++report.points_in_several_pieces;
  }
}

}  // namespace

PieceReport check_pieces(const PieceSet& pieces, const MeshSoup& exterior, const PieceCheckOptions& options) {
  if (exterior.triangles.empty()) throw InputError("exterior: no triangles");
  for (std::size_t p = 0; p < pieces.pieces.size(); ++p)
    for (std::size_t t = 0; t < pieces.pieces[p].triangles.size(); ++t)
      for (std::uint32_t v : pieces.pieces[p].triangles[t])
        if (v >= pieces.positions.size())
          throw RunError("piece " + std::to_string(p) + ": triangle " + std::to_string(t) + " has vertex " +
                         std::to_string(v) + " out of range (" + std::to_string(pieces.positions.size()) + " positions)");
  const Bvh exterior_bvh = build_bvh(exterior.positions, exterior.triangles);
  PieceReport report;
  report.exterior_volume = signed_volume(exterior.positions, exterior.triangles);
  std::vector<CompactMesh> meshes;
  for (std::size_t p = 0; p < pieces.pieces.size(); ++p) {
    meshes.push_back(compact(pieces, pieces.pieces[p]));
    report.pieces.push_back(check_piece(pieces, p, meshes.back(), options, report.failures));
    report.volume_sum += report.pieces.back().volume;
  }
  report.volume_relative_error = std::abs(report.volume_sum - report.exterior_volume) / std::abs(report.exterior_volume);
  if (!(report.volume_relative_error <= options.volume_tolerance))
    report.failures.push_back("pieces: volumes sum to " + std::to_string(report.volume_sum) + " but the exterior's is " +
                              std::to_string(report.exterior_volume) + " (relative error " +
                              std::to_string(report.volume_relative_error) + ")");
  check_points(meshes, exterior_bvh, options, report);
  if (report.points_in_no_piece)
    report.failures.push_back("pieces: " + std::to_string(report.points_in_no_piece) + " of " +
                              std::to_string(report.points_tested) + " points inside the exterior lie in no piece");
  if (report.points_in_several_pieces)
    report.failures.push_back("pieces: " + std::to_string(report.points_in_several_pieces) + " of " +
                              std::to_string(report.points_tested) + " points inside the exterior lie in several pieces");
  return report;
}

void require_valid_pieces(const PieceReport& report) {
  if (report.ok()) return;
  std::string message = "invalid pieces:";
  for (const std::string& f : report.failures) message += "\n  " + f;
  throw RunError(message);
}

}  // namespace fracref
