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

/// Locates every rim vertex of S on B and splits every rim edge whose ends share no triangle of
/// B where its trace (trace_on_exterior) crosses B's edges: the face on the edge becomes a fan
/// from its opposite corner over the trace's points (a face with two or three traced sides, a
/// fan from its centroid). New vertices and faces are appended (faces keep their pieces), the
/// adjacency rebuilt. Rim vertices are moved to their locations (as floats). Then S is trimmed to
/// B (trim_to_exterior): cut along S ∩ B, the parts outside B dropped.
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
