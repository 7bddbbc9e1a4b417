#pragma once
// Internal to the pieces room: what build_pieces tries when an attempt fails (the errors an
// attempt throws, and the changes to S the next attempt makes). Not part of the public API.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "pieces/pieces_internal.hpp"
#include "util/error.hpp"

namespace fracref::pieces_detail {

/// A vertex's push grows by this factor times its poke depth per round.
inline constexpr double kPushFactor = 1.25;
/// At most this many push rounds; then a poking vertex is contracted instead.
inline constexpr std::size_t kMaxPushRounds = 8;
/// A push that did not take a vertex's poke at least this much shallower will not: the poke is
/// not this vertex's to fix by moving (such pokes can grow with every push, for rounds of
/// rebuilds until kMaxPushRounds), so the vertex is contracted at once instead.
inline constexpr double kFutilePush = 0.75;
/// A folded vertex is relaxed this much further toward its neighbours' centroid per attempt.
inline constexpr double kRelaxStep = 0.25;

/// The faces of S whose fracture polygons cannot be triangulated (all of them in one build, so
/// that one retry deals with them all). build_pieces starts again with each face left out when it
/// has two or three boundary edges (a flap: all its corners lie on B), or with its boundary edge
/// traced along the face's normal when it has one.
struct UntriangulatedFaces : RunError {
  struct Face {
    std::string what;
    std::uint32_t face;
    bool flap;
    glm::uvec2 boundary_edge;  // S vertices of its boundary edge (one boundary side)
  };
  explicit UntriangulatedFaces(std::vector<Face> all) : RunError(all.front().what), faces(std::move(all)) {}
  std::vector<Face> faces;
};

/// Fracture triangles poking out of B: build_pieces starts again with their S vertices off B
/// pushed inward, a quarter farther than each alone would have to go to take the deepest poke
/// back (a vertex at most its shortest edge in all, over kMaxPushRounds rounds).
struct PokingOut : RunError {
  struct Vertex {
    double depth, limit;
    glm::dvec3 at;
    std::vector<std::uint32_t> neighbours;  // its neighbours in S, nearest first
    glm::dvec3 direction{0.0};  // which way to push (see Push)
  };
  explicit PokingOut(std::map<std::uint32_t, Vertex> v) : RunError("poking out"), vertices(std::move(v)) {}
  std::map<std::uint32_t, Vertex> vertices;

  /// The deepest poke, for a message.
  std::string describe() const;
};

/// Fracture triangles crossing each other once the rim's traces bent them toward B (a pleat of
/// S, a few tiny faces folded onto each other next to the rim): build_pieces starts again with
/// the shortest edge at these S vertices contracted, or when none is left, the vertices relaxed
/// toward their neighbours.
struct Folded : RunError {
  struct Vertex {
    glm::dvec3 at;
    std::uint32_t nearest;  // the neighbour at its shortest edge
    double shortest;
  };
  Folded(std::string what, std::map<std::uint32_t, Vertex> v) : RunError(std::move(what)), vertices(std::move(v)) {}
  std::map<std::uint32_t, Vertex> vertices;
};

/// What build_pieces changes between attempts (faces in input numbering).
struct Retries {
  std::vector<std::uint32_t> left_out;  // flaps to leave out
  /// Faces whose boundary edge is traced along their normal -> the push round it was decided in.
  std::map<std::uint32_t, std::size_t> along_normal;
  std::map<std::uint32_t, Push> pushed;  // S vertex -> how far (and which way) it is pushed into B
  std::map<std::uint32_t, double> relaxed;  // S vertex -> fraction of the way to its neighbours
  std::vector<std::pair<std::uint32_t, std::uint32_t>> contractions;  // S edges (gone, keep)
  std::size_t push_rounds = 0, attempts = 0;

  /// After faces could not be triangulated; false (why: the face's message) when nothing is left
  /// to try for one of them.
  bool next(const UntriangulatedFaces& failed, std::string& why);

  /// One face of the above: a flap is left out (false when it was already); otherwise its
  /// boundary edge is traced along its normal, back to the usual plane after a push round, and
  /// then the edge is contracted (each direction once; false when both were tried).
  bool next(const UntriangulatedFaces::Face& failed);

  /// After fracture triangles poked out of B: each poking vertex is pushed kPushFactor times
  /// its depth further (in `pushed`, and push_rounds counts the call). A vertex is contracted
  /// into its nearest neighbour not tried yet (and its push dropped) instead when the push
  /// would pass its limit, push_rounds reached kMaxPushRounds, or the push is futile: it was
  /// pushed before and its poke is still at least kFutilePush times the depth that decided the
  /// last push. False (why: names the vertex) when every neighbour was tried.
  bool next(const PokingOut& poking, std::string& why);

  /// After the traces of two S boundary edges crossed: the vertex they share (a zigzag of the
  /// rim) is contracted into a neighbour on the rim, else an end of one edge into the other (the
  /// shorter edge first; a trace crossing itself, its edge); false when every such contraction
  /// was tried before.
  bool next(const TracesCross& crossed, const std::vector<glm::dvec3>& x);

  /// After fracture triangles crossed each other: the vertex with the shortest edge (neither it
  /// nor its nearest neighbour contracted yet) is contracted into that neighbour; when there is
  /// none, every vertex is relaxed kRelaxStep further. False when a vertex was relaxed all the
  /// way already.
  bool next(const Folded& folded, std::string& why);
};

}  // namespace fracref::pieces_detail
