#pragma once
// The canonical fracture surface S (paper section 4.1): the non-manifold triangle surface inside
// the object that separates it into pieces. Every face is stored once, with the two pieces it
// separates; junctions where three or more pieces meet are edges shared by three or more faces,
// which is why S is flat arrays (the ones the GPU sees) and not a halfedge mesh.
//
// Connectivity (faces, face_pieces, vertex_flags' kVertexOriginal bit) is the source of truth;
// everything else is derived by rebuild_adjacency(), which must run after every topology edit.
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace fracref {

/// Per-vertex bits of FractureSurface::vertex_flags.
enum VertexFlag : std::uint32_t {
  kVertexBoundary = 1,     ///< derived: on a boundary edge (an edge of one face), i.e. on B
  kVertexNonManifold = 2,  ///< derived: on a non-manifold edge, or a pinch vertex (see below)
  kVertexOriginal = 4,     ///< kept: a vertex of the low-resolution input, not a refinement
};
inline constexpr std::uint32_t kVertexFlagMask = kVertexBoundary | kVertexNonManifold | kVertexOriginal;

/// Values of FractureSurface::edge_special.
enum EdgeKind : std::uint8_t {
  kEdgeRegular = 0,      ///< exactly two faces
  kEdgeBoundary = 1,     ///< one face: the edge lies on the exterior B
  kEdgeNonManifold = 2,  ///< three or more faces: a junction of pieces
};

/// Returned by find_edge() when there is no such edge.
inline constexpr std::uint32_t kNoEdge = 0xffffffffu;

/// The fracture surface S as flat arrays.
///
/// Face sides: side 2f+0 is the front of face f (the side its right-hand-rule normal points to),
/// side 2f+1 its back. face_pieces[f] = (front piece, back piece).
///
/// A vertex is non-manifold when it lies on a non-manifold edge, or when it is a pinch vertex:
/// its incident faces fall into two or more fans that share no edge (sheets touching at a point).
struct FractureSurface {
  // geometry and connectivity (the source of truth)
  std::vector<glm::vec4> positions;         ///< xyz, w = 1
  std::vector<glm::uvec4> faces;            ///< xyz = vertex ids in the face's orientation, w = 0
  std::vector<glm::ivec2> face_pieces;      ///< (front, back): the face normal points INTO front
  std::vector<std::uint32_t> vertex_flags;  ///< VertexFlag bits; kVertexOriginal kept, others derived
  int piece_count = 0;

  // derived by rebuild_adjacency(); read-only for users
  // (offsets start as {0}, so that an empty, default-constructed surface is valid)
  std::vector<std::uint32_t> vf_offsets{0}, vf_faces;  ///< vertex -> faces CSR (faces ascending)
  std::vector<glm::uvec2> edges;                    ///< undirected (a < b), sorted lexicographically
  std::vector<std::uint32_t> ef_offsets{0}, ef_faces;  ///< edge -> faces CSR (ascending), any count
  std::vector<std::uint32_t> face_edges;            ///< 3 per face: edge of (v0v1, v1v2, v2v0)
  std::vector<std::uint8_t> edge_special;           ///< EdgeKind per edge
  std::vector<std::uint32_t> side_component;        ///< per face side (2f front, 2f+1 back)
  std::uint32_t component_count = 0;
  /// Each canonical vertex's copies in the per-piece meshes (the paper's linked list), CSR
  /// over vertices, pieces ascending: (piece, local index of the vertex in piece_mesh()).
  std::vector<std::uint32_t> copy_offsets{0};
  std::vector<glm::uvec2> copies;
  std::vector<std::uint32_t> piece_vertex_counts;  ///< per piece: vertices of its mesh

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t face_count() const { return faces.size(); }
};

/// Side index of face f: front (2f) or back (2f+1).
inline std::uint32_t face_side(std::uint32_t face, bool back) { return 2 * face + (back ? 1u : 0u); }
/// The piece on a face side.
inline int side_piece(const FractureSurface& s, std::uint32_t side) {
  const glm::ivec2 p = s.face_pieces[side / 2];
  return (side & 1u) ? p.y : p.x;
}

/// One piece's share of S as an ordinary triangle mesh, oriented outward from the piece.
struct PieceMesh {
  std::vector<glm::vec3> positions;                 ///< per local vertex
  std::vector<glm::uvec3> triangles;                ///< local vertex ids, outward winding
  std::vector<std::uint32_t> vertex_to_canonical;   ///< local vertex -> vertex of S (ascending)
  std::vector<std::uint32_t> face_to_canonical;     ///< local triangle -> face of S (ascending)
};

/// Builds S from connectivity: marks every vertex kVertexOriginal, sets positions' w to 1 and
/// faces' w to 0, then calls rebuild_adjacency().
/// \throw InputError naming the vertex or face: non-finite position, face vertex out of range,
///        repeated vertex in a face, piece outside [0, piece_count), front == back, two faces on
///        the same vertex set, face and face_pieces counts that differ, negative piece_count.
FractureSurface make_fracture_surface(std::vector<glm::vec4> positions, std::vector<glm::uvec4> faces,
                                      std::vector<glm::ivec2> face_pieces, int piece_count);

/// Recomputes every derived array of `s` and the boundary / non-manifold bits of vertex_flags
/// (kVertexOriginal is kept) from positions, faces and face_pieces. Deterministic, O(n log n).
/// vertex_flags is first resized to the vertex count: vertices appended by a topology edit may
/// leave it short, and get no kVertexOriginal bit.
///
/// Side components: a flood fill over face sides. Across a regular edge, consistently wound faces
/// join front to front and back to back, oppositely wound ones front to back. Across a
/// non-manifold edge the faces are ordered by the angle of their opposite vertex around the edge
/// (ties by face id) and each face joins its angular neighbour on the side facing their common
/// wedge. Nothing crosses a boundary edge. Components are numbered by their lowest side.
/// Copies: piece p's mesh holds the faces with p on either side; its vertices are numbered in
/// ascending canonical order.
/// \pre face indices in range and no face repeats a vertex (validate() checks this first).
/// \throw RunError when a face index is out of range (the rest of the precondition is unchecked).
void rebuild_adjacency(FractureSurface& s);

/// A copy of s's primary arrays (positions, faces, face_pieces, vertex_flags, piece_count) with
/// every derived array empty: the start of a fresh rebuild or of a scratch edit.
FractureSurface primary_copy(const FractureSurface& s);

/// rebuild_adjacency after edge flips of regular edges between faces of the same piece pair:
/// only the vertex-face lists and the edge table change (each vertex keeps its pieces, each face
/// its sides and component, special edges stay), so only those are rebuilt.
/// \pre the flips were of that kind (validate() compares every derived array with a fresh build).
void rebuild_after_flips(FractureSurface& s);

/// rebuild_adjacency after splits that appended vertices from `first_vertex` on, each inside a
/// face or an edge, and faces from `first_face` on, face f split off face origin[f - first_face]
/// (an older face, or one appended before f) with its winding and pieces; every old face keeps
/// its id, winding and pieces. The vertex-face lists and the edge table are rebuilt; the old
/// vertices' flags and copies and the old faces' components are kept (a split changes none of
/// them), the new ones derived from their edges and origins: a full rebuild's flags and copies
/// cost ten times as much on a large surface.
/// \pre the derived arrays were current before the splits (validate() compares every derived
/// array with a fresh build).
/// \throw RunError when origin does not hold one older face per new face.
void rebuild_after_splits(FractureSurface& s, std::size_t first_vertex, std::size_t first_face,
                          std::span<const std::uint32_t> origin);

/// Only the edge table of rebuild_adjacency (edges, ef_offsets, ef_faces, face_edges,
/// edge_special); vf, the vertex flags, components and copies are left as they were. For scratch
/// copies that only collision tests read. \pre face indices in range.
void rebuild_edge_table(FractureSurface& s);

/// Piece `piece`'s faces of S, wound outward from the piece (a face's winding is kept where the
/// piece is its back, reversed where it is its front), vertices numbered as in `copies`.
/// \throw RunError when piece is not in [0, piece_count).
PieceMesh piece_mesh(const FractureSurface& s, int piece);

/// S's positions in double precision (w dropped), for exact predicates and distance queries.
std::vector<glm::dvec3> double_positions(const FractureSurface& s);

/// p rounded to single precision and back: where a vertex placed at p is stored (positions are
/// floats), so that a test on p is a test on the stored vertex. Not spelled dvec3(vec3(p)): GCC
/// 12.2's SLP vectorizer (Debian 12's compiler, at -O2 and -O3) drops a double -> float ->
/// double round trip done on two neighbouring components at once and returns them unrounded.
/// The float copies below are made to exist, so the rounding happens.
inline glm::dvec3 stored_position(const glm::dvec3& p) {
  float f[3] = {float(p.x), float(p.y), float(p.z)};
#if defined(__GNUC__)
  asm("" : "+m"(f));
#endif
  return glm::dvec3(f[0], f[1], f[2]);
}

/// S's faces as vertex-id triples (pieces dropped).
std::vector<std::array<std::uint32_t, 3>> face_triangles(const FractureSurface& s);

/// The id of the undirected edge {a, b}, or kNoEdge. O(log edges). \pre adjacency is current.
std::uint32_t find_edge(const FractureSurface& s, std::uint32_t a, std::uint32_t b);

/// Whether face f traverses edge e from its smaller vertex to its larger one (two faces wind a
/// manifold edge consistently when they traverse it in opposite directions). \pre f has both of
/// e's vertices (false when it lacks the smaller one).
bool traverses_forward(const FractureSurface& s, std::uint32_t f, std::uint32_t e);

/// The piece of each side component, or -1 for a component whose sides carry different pieces
/// (which validate() reports). \pre adjacency is current.
std::vector<int> component_pieces(const FractureSurface& s);

/// "" when every invariant of S holds, else one message naming the first broken invariant and
/// its indices, e.g. "face 7: vertex 12 out of range (9 vertices)". Checked in this order:
/// array sizes; finite positions with w = 1 and known flag bits; face indices in range, no
/// repeated vertex, pieces in range with front != back; no two faces on the same vertex set;
/// every derived array equal to a fresh rebuild_adjacency() (vf, edges, ef, face_edges,
/// edge_special, vertex flags, components, copies); every side component carries one piece
/// (reported at the first edge joining two sides of different pieces); for every edge and piece,
/// the piece's outward faces at the edge are none, two in opposite directions, or one on a
/// boundary edge.
std::string validate(const FractureSurface& s);

/// validate() without its comparison of the derived arrays with a fresh rebuild: for a surface
/// whose adjacency rebuild_adjacency() (or rebuild_after_flips / rebuild_after_splits, whose
/// results the unit tests compare with fresh ones) has just built, where an edit is judged by
/// whether the new faces make a valid S, and the full check would rebuild it a second time.
/// \pre the adjacency was rebuilt after the last change to s.
std::string validate_rebuilt(const FractureSurface& s);

/// validate()'s checks of one edge at a time, at `edges` only: each piece's outward faces close up
/// at the edge (none, two in opposite directions, or one on a boundary edge), and the faces around
/// it join only sides of the same piece (the order of the sheets around a junction edge keeps the
/// pieces apart). "" when they hold, else one message naming the edge. For an edit that changes S
/// only at those edges, judged without a rebuild of the whole surface.
/// \pre the edge table (edges, ef, edge_special) current; indices in range.
std::string validate_edges(const FractureSurface& s, std::span<const std::uint32_t> edges);

/// validate(), throwing its message. For use after mutations in tests and debug builds.
/// \throw RunError with validate()'s message when an invariant is broken.
void validate_or_throw(const FractureSurface& s);

}  // namespace fracref
