#pragma once
// Pre-fractured pieces that nearly conform (issue 30): Blender Cell Fracture's margins and
// jitter, overlapping slivers, the two sides of a cut triangulated differently, n-gons, open or
// degenerate faces, pieces a small gap apart. They cannot give S from their own faces, so the
// exterior B names the material and the pieces only say which piece each point of it belongs
// to: B's inside is filled with the tet lattice of the cuts input (tet_lattice.hpp), each tet
// takes the piece whose generalized winding number (Jacobson et al. 2013) is largest at its
// centre, or, in a gap, the nearest piece, and S is the boundary between the labels
// (build_tet_model()). Rule documented in scenes/INPUTS.md, "Pieces that nearly conform".
#include <filesystem>
#include <string>
#include <vector>

#include "coarse/coarse_model.hpp"
#include "io/mesh_soup.hpp"

namespace fracref {

struct FitOptions {
  /// The widest gap between pieces, or between the pieces and B, that is closed: a fraction of
  /// B's bounding-box diagonal (scene key fracture.tolerance). A point of B farther than this
  /// from every piece is an error; hull faces of two pieces facing each other closer than this
  /// send conforming-looking pieces to the fit.
  double tolerance = 0.005;
  /// Lattice cell = B's bounding-box diagonal / this (scene key fracture.cells_per_diagonal),
  /// doubled, up to max_cells_per_diagonal, while a piece gets no tet though its volume is at
  /// least an eighth of the cell's, as long as doubling leaves fewer pieces without a tet.
  double cells_per_diagonal = 24.0;
  double max_cells_per_diagonal = 128.0;
  /// Isosurface stuffing: a lattice vertex closer to B than this fraction of an edge snaps onto B.
  double warp = 0.3;
  /// A label's face-connected parts other than its largest with at most this fraction of the
  /// largest part's tets are given to the label they share most faces with (noise of a sliver).
  double island_fraction = 0.05;
  /// As TetModelOptions::own_vertices (rigid animation: each piece moves its own copies).
  bool own_vertices = false;
};

/// Builds the coarse model of `pieces` by labelling B's inside (see the file comment), then
/// cleaning the labels up: stray islands merged (island_fraction), wedges S cannot represent at
/// an edge relabelled (clean_label_fans(), as for cuts). While a piece of at least an eighth of a cell's volume gets no
/// tet the lattice's cell is halved (up to max_cells_per_diagonal, and only while that leaves
/// fewer pieces without a tet); a piece that still has none then gets the one tet nearest it
/// (model.fit.grown). Piece i of the model is pieces[i] (named by it); a label that
/// still falls into several parts gets further pieces named "<name>, part k", as
/// build_tet_model() does. model.fit records the reason, the tolerance, the cell, the gap and
/// overlap volumes found and the clean-ups.
/// \pre exterior is closed and outward (the pipeline checks it with make_exterior); the pieces
///      passed the checks of build_pieces_model() that throw a plain InputError.
/// \throw InputError naming pieces[0].file when a point of B lies farther than the tolerance from
///        every piece (with the point and distance); naming a piece's file and name when no tet
///        lies near it (outside B); as build_tet_model(); naming exterior_file when B has no face
///        or no lattice tet lies inside it.
CoarseModel fit_pieces_model(const MeshSoup& exterior, const std::string& exterior_file,
                             const std::vector<PieceInput>& pieces, const std::string& reason, const FitOptions& options = {});

/// The pieces' exact model (build_pieces_model()) when they conform: faces matched corner for
/// corner, S not empty (or a single piece), and no two pieces' hull faces facing each other
/// closer than the tolerance; fit_pieces_model() otherwise, with the reason.
/// \throw InputError as build_pieces_model()'s plain InputErrors and fit_pieces_model().
CoarseModel build_pieces_or_fit(const MeshSoup& exterior, const std::string& exterior_file,
                                const std::vector<PieceInput>& pieces, const PiecesOptions& exact = {},
                                const FitOptions& fit = {});

/// Index of a hull face of `model` that faces (opposite normal, within 25 degrees) a hull face
/// of another piece closer than `distance` from its centre; -1 when none.
std::int64_t find_hull_gap(const CoarseModel& model, double distance);

}  // namespace fracref
