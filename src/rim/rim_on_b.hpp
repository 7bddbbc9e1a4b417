#pragma once
// S's rim embedded in B (issue 29): every rim vertex of S (kVertexBoundary) has a location on B,
// and every rim edge lies in one triangle of B, so B can be cut along the rim exactly, one
// triangle at a time, with no tracing after the refinement. embed_rim() makes it so once, on the
// coarse S; the refiner keeps it (a rim edge is only ever split, at a point of its own segment,
// which lies in the same triangle: location_between()).
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "rim/exterior_mesh.hpp"
#include "surface/fracture_surface.hpp"

namespace fracref::rim {

/// Per vertex of S, where it lies on B.
struct RimOnB {
  std::vector<Location> at;        ///< per S vertex, meaningful where on_b
  std::vector<std::uint8_t> on_b;  ///< per S vertex: a rim vertex with a location
};

/// A vertex embed_rim() added to S, as the weighted point of older vertices it was created at
/// (the refinement tree's convention): a point where a rim edge's trace crosses a B edge, on the
/// chord of that edge at the fraction of the trace's length; or the centroid of a face with two
/// or three traced sides; or a point of S ∩ B made by trim_to_exterior (on an S edge, its
/// 2-parent point; inside a face, its 3-parent barycentric point).
struct EmbeddedVertex {
  std::uint32_t vertex = 0;
  std::array<std::uint32_t, 3> parents{};
  glm::dvec3 weights{0.0};
};

struct EmbedOptions {
  /// Largest distance of a rim vertex from B, relative to B's diagonal (the refiner projects in
  /// float); farther means S does not end on B.
  double snap_tolerance = 1e-4;
  /// Barycentric weights below this are zeroed when locating a rim vertex, so one that was meant
  /// to lie on a B edge or vertex (up to float noise) lands exactly on it.
  double location_epsilon = 1e-6;
  /// B vertices closer than this (relative to B's diagonal) to a trace's plane are on it.
  double plane_epsilon = 1e-9;
  /// When set, a rim vertex with a location here (on_b) keeps it instead of being located again
  /// from its float position (the refiner's slid rim: the float rounding of a point on a B edge
  /// can lie a hair inside the next triangle, and its rim edge would be split there, a second rim
  /// point at its place). Rim vertices beyond its size, or without a location, are located.
  const RimOnB* known = nullptr;
};

/// What trim_to_exterior (rim/trim_to_exterior.hpp) did.
struct TrimStats {
  std::uint32_t cut_faces = 0;      ///< faces of S re-triangulated along B
  std::uint32_t removed_faces = 0;  ///< faces of S dropped, whole or in part: outside B
  std::uint32_t new_vertices = 0;   ///< points of S ∩ B added as rim vertices
};

struct Embedding {
  RimOnB rim;
  std::vector<EmbeddedVertex> added;  ///< ascending vertex; the new vertices are the last of S
  TrimStats trim;                     ///< S cut to B (rim/trim_to_exterior.hpp)
};

/// Locates every rim vertex of S on B (rim vertices are moved to their locations, as floats) and
/// embeds every rim edge whose ends share no triangle of B (a chord of B) along its trace across
/// B's edges. A face with such sides is split, one face at a time, by the first of these that
/// keeps S embedded, each checked before it is made (its triangles face as the face did, none is
/// a flap lying on B, none meets B other than at its rim points, nor another face of S, and no
/// trace runs through a B vertex that holds a rim vertex):
///  - the traces at right angles to B (trace_on_exterior), the face a fan from the corner opposite
///    its one traced side, or from its centroid;
///  - the traces in the face's own plane (trace_in_plane), the flat polygon they make with the
///    face's corners triangulated in that plane.
/// A face with neither (a chord over a concave part of B, outside it, with its face crossing B)
/// is left to the trim: S is cut along S ∩ B and the parts outside B dropped (trim_to_exterior),
/// and what is left of the chords, with the edges of the flaps the trim dropped, is split the
/// same way, in rounds, with two more checked splits:
///  - the flat split whose traces leave their start the other way along the face's section of
///    B (a chord straight across B's inside, whose straightest trace runs round S's side);
///  - the bisection of one chord at the point of B closest to its midpoint, the face halved
///    there (its halves are split in the next round);
/// a face there with no checked split becomes the fan all the same, and S is trimmed once more.
/// New vertices and faces are appended (faces keep their pieces), the adjacency rebuilt.
/// \pre s's adjacency current.
/// \throw RunError naming the vertex or edge: a rim vertex farther than snap_tolerance from B,
///        two rim vertices on one B vertex, a rim edge that cannot be traced, a trace through a
///        B vertex that holds a rim vertex.
Embedding embed_rim(FractureSurface& s, const ExteriorMesh& m, const EmbedOptions& options = {});

/// The rim vertex created where rim edge a-b is split at parameter t (from a): its location on
/// the segment between theirs. \pre rim.on_b[a] and rim.on_b[b], their locations share a triangle.
Location split_location(const ExteriorMesh& m, const RimOnB& rim, std::uint32_t a, std::uint32_t b, double t);

/// The first rim edge of S (in edge order) whose ends do not lie in one triangle of B, or a rim
/// vertex without a location: "" when every rim edge is embedded, else a message naming it.
std::string find_unembedded_rim(const FractureSurface& s, const ExteriorMesh& m, const RimOnB& rim);

}  // namespace fracref::rim
