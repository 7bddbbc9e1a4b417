// preview.png: the pieces laid out side by side, each turned so that its fracture faces face the
// camera. Drawn in place and pushed apart, pieces hide each other's fracture faces from any one
// camera (a piece's faces look at its neighbours), which is what the picture is for.
#include <algorithm>
#include <cmath>
#include <limits>
#include <functional>
#include <optional>
#include <unordered_map>

#include "pipeline/job_outputs.hpp"
#include "pipeline/surface_preview.hpp"

namespace fracref {
namespace {

// Where the camera is: it looks along −z; a view tilted a little off the faces' normal so the
// relief of the fracture surface reads in the shading.
const glm::dvec3 kToCamera = glm::normalize(glm::dvec3(0.25, 0.30, 1.0));
// A second view of a piece when the first shows less than this fraction of its fracture area.
constexpr double kSeenEnough = 0.7;
constexpr double kGap = 0.15;  // between cells, as a fraction of the largest piece

glm::dvec3 face_normal(const PieceSet& set, const std::array<std::uint32_t, 3>& t) {
  return 0.5 * glm::cross(set.positions[t[1]] - set.positions[t[0]], set.positions[t[2]] - set.positions[t[0]]);
}

// The rotation taking unit vector `from` to unit vector `to` (Rodrigues); a half turn about an
// axis normal to both when they are opposite.
glm::dmat3 rotation_between(const glm::dvec3& from, const glm::dvec3& to) {
  const glm::dvec3 axis = glm::cross(from, to);
  const double c = glm::dot(from, to), s = glm::length(axis);
  if (s < 1e-12) {
    if (c > 0.0) return glm::dmat3(1.0);
    const glm::dvec3 any = std::abs(from.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 k = glm::normalize(glm::cross(from, any));
    return 2.0 * glm::outerProduct(k, k) - glm::dmat3(1.0);
  }
  const glm::dvec3 k = axis / s;
  const glm::dmat3 K(glm::dvec3(0, k.z, -k.y), glm::dvec3(-k.z, 0, k.x), glm::dvec3(k.y, -k.x, 0));
  return glm::dmat3(1.0) + s * K + (1.0 - c) * K * K;
}

// The views of a piece: the direction its fracture faces look on average, and, when that shows
// too little of them (a piece with fracture faces on opposite sides), the mean of the rest.
std::vector<glm::dvec3> piece_views(const PieceSet& set, const PieceSet::Piece& piece) {
  glm::dvec3 mean(0.0);
  double total = 0.0;
  for (std::size_t f = 0; f < piece.triangles.size(); ++f) {
    if (!piece.inside[f]) continue;
    const glm::dvec3 n = face_normal(set, piece.triangles[f]);
    mean += n, total += glm::length(n);
  }
  if (!(glm::length(mean) > 1e-9 * total)) return {glm::dvec3(0.0, 0.0, 1.0)};
  const glm::dvec3 first = glm::normalize(mean);
  glm::dvec3 rest(0.0);
  double seen = 0.0;
  for (std::size_t f = 0; f < piece.triangles.size(); ++f) {
    if (!piece.inside[f]) continue;
    const glm::dvec3 n = face_normal(set, piece.triangles[f]);
    if (glm::dot(n, first) > 0.0) seen += glm::length(n);
    else rest += n;
  }
  if (seen >= kSeenEnough * total || !(glm::length(rest) > 0.0)) {
    std::vector<glm::dvec3> normals;
    for (std::size_t f = 0; f < piece.triangles.size(); ++f)
      if (piece.inside[f]) normals.push_back(face_normal(set, piece.triangles[f]));
    return {towards_walls(normals, first)};
  }
  return {first, glm::normalize(rest)};
}

// One piece as seen along `view`, turned so that `view` points at the camera, centred on 0. Its
// fracture faces are coloured by ζ at each pixel's point of the piece (a fruit cube cut across
// shows as a square, not as the triangles around it) and lit smoothly (kPreviewCrease), apart
// from the exterior's.
PreviewMesh turned_piece(const PieceSet& set, std::size_t p, const glm::dvec3& view, const FractureColour& color_at,
                         const glm::vec3& plain, const glm::vec3& exterior) {
  const PieceSet::Piece& piece = set.pieces[p];
  const glm::dmat3 r = rotation_between(view, kToCamera);
  PreviewMesh m;
  std::vector<int> groups;
  std::unordered_map<std::uint32_t, std::uint32_t> local;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (std::size_t f = 0; f < piece.triangles.size(); ++f) {
    std::array<std::uint32_t, 3> t{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = piece.triangles[f][k];
      const auto [it, added] = local.try_emplace(v, std::uint32_t(m.positions.size()));
      if (added) {
        m.positions.push_back(r * set.positions[v]);
        lo = glm::min(lo, m.positions.back()), hi = glm::max(hi, m.positions.back());
      }
      t[k] = it->second;
    }
    m.triangles.push_back(t);
    m.triangle_colors.push_back(piece.inside[f] ? plain : exterior);
    groups.push_back(piece.inside[f] ? 1 : 0);
  }
  for (glm::dvec3& x : m.positions) x -= 0.5 * (lo + hi);
  smooth_corner_normals(m, kPreviewCrease, groups);
  if (color_at) m.paint = paint_piece(set, p, color_at, exterior);
  return m;
}

glm::dvec3 extent(const PreviewMesh& m) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const glm::dvec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return m.positions.empty() ? glm::dvec3(0.0) : hi - lo;
}

}  // namespace

std::function<glm::vec3(std::size_t, const glm::dvec3&)> paint_piece(const PieceSet& set, std::size_t p,
                                                                     const FractureColour& colour, glm::vec3 exterior) {
  return [&set, p, &colour, exterior](std::size_t f, const glm::dvec3& b) {
    if (!set.pieces[p].inside[f]) return exterior;
    const auto& t = set.pieces[p].triangles[f];
    return colour(b.x * set.positions[t[0]] + b.y * set.positions[t[1]] + b.z * set.positions[t[2]]);
  };
}

Image preview_pieces(const PieceSet& set, const Grid3* zeta, const std::array<Grid3, 3>* albedo) {
  const std::optional<StrengthRamp> ramp = zeta ? std::optional<StrengthRamp>(std::in_place, *zeta) : std::nullopt;
  const FractureColour color_at = ramp ? fracture_colour(albedo, *ramp) : FractureColour{};
  // Light beside ζ's ramp; darker beside the materials' own colours, which include white marble.
  const glm::vec3 exterior = albedo ? glm::vec3(0.50f, 0.52f, 0.56f) : glm::vec3(0.86f, 0.86f, 0.88f);
  std::vector<PreviewMesh> meshes;
  for (std::size_t p = 0; p < set.pieces.size(); ++p)
    for (const glm::dvec3& view : piece_views(set, set.pieces[p]))
      meshes.push_back(turned_piece(set, p, view, color_at, piece_color(int(p)), exterior));
  // One scale for every piece (their sizes compare), in a grid whose shape suits a 16:10 picture.
  glm::dvec3 cell(0.0);
  for (const PreviewMesh& m : meshes) cell = glm::max(cell, extent(m));
  cell *= 1.0 + kGap;
  const int n = int(meshes.size());
  int columns = 1;
  double best = 0.0;
  for (int c = 1; c <= n; ++c) {  // the column count that draws the pieces largest
    const double scale = std::min(16.0 / (double(c) * cell.x), 10.0 / (double((n + c - 1) / c) * cell.y));
    if (scale > best * (1.0 + 1e-9)) best = scale, columns = c;
  }
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 at(double(i % columns) * cell.x, -double(i / columns) * cell.y, 0.0);
    for (glm::dvec3& q : meshes[std::size_t(i)].positions) q += at;
  }
  RenderOptions ro;
  ro.width = 1600;
  ro.height = 1000;
  ro.view_direction = glm::dvec3(0.0, 0.0, -1.0);
  ro.light_direction = glm::dvec3(-0.3, -0.5, -1.0);
  return render_preview(meshes, ro);
}

}  // namespace fracref
