#pragma once
// Internal steps of rebuild_adjacency(), shared by the builder and validate(). Not a public API.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "surface/fracture_surface.hpp"

namespace fracref::surface_detail {

/// vf_offsets / vf_faces. \pre face indices in range.
void build_vertex_faces(FractureSurface& s);
/// edges, ef_offsets / ef_faces, face_edges, edge_special.
void build_edges(FractureSurface& s);
/// Boundary and non-manifold bits (kVertexOriginal kept). \pre vf and edges built.
void build_vertex_flags(FractureSurface& s);
/// side_component, component_count. \pre edges built.
void build_components(FractureSurface& s);
/// copy_offsets, copies, piece_vertex_counts. \pre vf built.
void build_copies(FractureSurface& s);
/// The vertex flags, components and copies of the vertices and faces that splits appended, the
/// rest kept (see rebuild_after_splits). \pre vf and edges built.
void extend_after_splits(FractureSurface& s, std::size_t first_vertex, std::size_t first_face,
                         std::span<const std::uint32_t> origin);

/// Two face sides found to face the same region across an edge.
struct SideJoin {
  std::uint32_t edge, a, b;
};
/// Every join, in edge order, as build_components() uses them. \pre edges built.
std::vector<SideJoin> side_joins(const FractureSurface& s);
/// The joins across edge e, appended to `joins`. \pre edges built.
void side_joins_at(const FractureSurface& s, std::uint32_t e, std::vector<SideJoin>& joins);

/// "face g: duplicate of face f (vertices a b c)" for the lowest face g whose vertex set an
/// earlier face f already has, or "". \pre indices in range.
std::string first_duplicate_face(const std::vector<glm::uvec4>& faces);

/// How many edge-connected fans the faces around vertex v form. \pre vf and edges built.
std::uint32_t fan_count(const FractureSurface& s, std::uint32_t v, std::vector<glm::uvec2>& scratch);

}  // namespace fracref::surface_detail
