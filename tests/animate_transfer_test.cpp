// Deformation transfer to the high-resolution pieces (paper section 5): rigid and affine motion
// reproduced at every vertex (refined fracture vertices, exterior vertices, crossing points),
// the fracture-time rule (shared vertices stay together until the coarse copies separate),
// and the frame files.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "animate/animate.hpp"
#include "coarse_test_support.hpp"
#include "geom/shapes.hpp"
#include "io/mesh_io.hpp"
#include "rim/rim_on_b.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

// Two unit cubes side by side, cut at x = 1: piece 0 is x < 1, piece 1 is x > 1. The vertices on
// x = 1 are duplicated for piece 1 (as a simulator does where a crack opens), so the pieces can
// separate. S is refined by face splits and its new vertices pushed off the plane, so that the
// refined vertices are not at their tree's interpolated position.
struct Scene {
  CoarseModel model;
  MeshSoup exterior;
  std::size_t rim_added = 0;  ///< vertices embed_rim added to S
  RefinementTree tree;
  FractureSurface refined;
  PieceSet pieces;
  std::vector<int> vertex_piece;  // per model vertex
};

// The pipeline's order: S's rim embedded in B, its new vertices entered in the refinement tree (as
// the refiner does), then the pieces.
void embed_and_build(Scene& sc) {
  const rim::ExteriorMesh m = rim::make_exterior_mesh(sc.exterior);
  const rim::Embedding e = rim::embed_rim(sc.refined, m);
  sc.rim_added = e.added.size();
  for (const rim::EmbeddedVertex& a : e.added) {
    sc.tree.parents.push_back(glm::uvec3(a.parents[0], a.parents[1], a.parents[2]));
    sc.tree.weights.push_back(glm::vec3(a.weights));
  }
  sc.pieces = build_pieces(sc.refined, m, e.rim);
}

MeshSoup box_soup(glm::dvec3 lo, glm::dvec3 hi, int n) {
  const TriangleSoup t = make_box(lo, hi, n);
  MeshSoup soup;
  soup.positions = t.positions;
  soup.triangles = t.triangles;
  soup.polygons = t.triangles.size();
  for (std::uint32_t i = 0; i < t.triangles.size(); ++i) soup.triangle_polygon.push_back(i);
  return soup;
}

TetMesh cracked_box() {
  TetMesh mesh = test::kuhn_box(2, 1, 1, [](glm::dvec3 c) { return c.x < 1.0 ? 0 : 1; });
  std::map<std::uint32_t, std::uint32_t> duplicate;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.labels[t] != 1) continue;
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t v = mesh.tets[t][k];
      if (mesh.vertices[v].x != 1.0) continue;
      auto [it, added] = duplicate.try_emplace(v, std::uint32_t(mesh.vertices.size()));
      if (added) mesh.vertices.push_back(mesh.vertices[v]);
      mesh.tets[t][k] = it->second;
    }
  }
  return mesh;
}

Scene make_scene(int exterior_cells, int split_rounds = 2) {
  Scene sc;
  sc.model = build_tet_model(cracked_box(), nullptr);
  sc.exterior = box_soup({0, 0, 0}, {2, 1, 1}, exterior_cells);
  sc.refined = sc.model.surface;
  sc.tree = RefinementTree::identity(sc.refined.vertex_count());
  for (int round = 0; round < split_rounds; ++round) {
    std::vector<SplitRequest> requests;
    for (std::uint32_t f = 0; f < sc.refined.face_count(); ++f)
      requests.push_back({SplitRequest::kFace, f, glm::vec3(0.3f, 0.3f, 0.4f)});
    apply_splits(sc.refined, sc.tree, requests);
  }
  for (std::size_t v = sc.model.surface.vertex_count(); v < sc.refined.vertex_count(); ++v)
    sc.refined.positions[v].x += 0.08f * std::sin(float(v));
  validate_or_throw(sc.refined);
  embed_and_build(sc);
  sc.vertex_piece.assign(sc.model.vertices.size(), -1);
  for (std::size_t t = 0; t < sc.model.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) sc.vertex_piece[sc.model.tets[t][k]] = sc.model.tet_piece[t];
  return sc;
}

using Motion = std::function<glm::dvec3(int piece, std::size_t frame, const glm::dvec3& x)>;

CoarseAnimation animate_model(const Scene& sc, std::size_t frames, const Motion& motion) {
  CoarseAnimation a;
  for (std::size_t t = 0; t < frames; ++t) {
    std::vector<glm::dvec3> x;
    for (std::size_t v = 0; v < sc.model.vertices.size(); ++v) x.push_back(motion(sc.vertex_piece[v], t, sc.model.vertices[v]));
    a.frames.push_back(std::move(x));
  }
  return a;
}

glm::dmat3 rotation(double angle, glm::dvec3 axis) {
  axis = glm::normalize(axis);
  const double c = std::cos(angle), s = std::sin(angle);
  const glm::dmat3 K(0, axis.z, -axis.y, -axis.z, 0, axis.x, axis.y, -axis.x, 0);
  return glm::dmat3(1.0) + s * K + (1 - c) * K * K;
}

// Every vertex of piece p in every frame must be at motion(p, t, X).
void expect_motion(const Scene& sc, const AnimationResult& r, const Motion& motion, double tol, int only_piece = -1) {
  for (std::size_t t = 0; t < r.frames.size(); ++t)
    for (std::size_t p = 0; p < r.layout.vertices.size(); ++p) {
      if (only_piece >= 0 && int(p) != only_piece) continue;
      for (std::size_t i = 0; i < r.layout.vertices[p].size(); ++i) {
        const std::uint32_t v = r.layout.vertices[p][i];
        const glm::dvec3 want = motion(int(p), t, sc.pieces.positions[v]);
        const glm::dvec3 got = r.frames[t][r.layout.offsets[p] + i];
        ASSERT_LT(glm::length(got - want), tol) << "frame " << t << " piece " << p << " vertex " << v << " origin "
                                                << sc.pieces.vertex_origin[v];
      }
    }
}

TEST(AnimateScene, HasRefinedExteriorAndSharedVertices) {
  const Scene sc = make_scene(2);
  ASSERT_EQ(sc.pieces.pieces.size(), 2u);
  EXPECT_EQ(sc.model.surface.vertex_count(), 4u);
  EXPECT_EQ(sc.refined.vertex_count(), 4u + 2u + 6u + sc.rim_added);  // and the rim's splits at B's edges
  const AnimationTransfer tr = build_transfer(sc.model, animate_model(sc, 1, [](int, std::size_t, glm::dvec3 x) { return x; }),
                                              sc.tree, sc.pieces);
  EXPECT_EQ(tr.source, DeformationSource::kTets);
  EXPECT_EQ(tr.nearest_fallbacks, 0u);
  EXPECT_EQ(tr.identity_anchors, 0u);
  // Shared: the S vertices, which include the 4 B vertices on the cut (the x = 1 grid line's edge
  // midpoints: the rim runs through them, and embed_rim's vertices there take them over).
  EXPECT_EQ(sc.rim_added, 4u);
  EXPECT_EQ(tr.shared.size(), sc.refined.vertex_count());
}

TEST(AnimateRigid, TetsMovedRigidlyPerPiece) {
  for (int cells : {2, 3}) {
    const Scene sc = make_scene(cells);
    const Motion motion = [](int piece, std::size_t t, glm::dvec3 x) {
      if (piece == 0 || t < 2) return x;
      return rotation(0.3 * double(t), {1, 2, 0.5}) * (x - glm::dvec3(1, 0.5, 0.5)) + glm::dvec3(1.0 + 0.4 * double(t), 0.1, -0.2);
    };
    const AnimationResult r = animate_pieces(sc.model, animate_model(sc, 6, motion), sc.tree, sc.pieces);
    ASSERT_EQ(r.frames.size(), 6u);
    expect_motion(sc, r, motion, 1e-9);
    for (std::int64_t f : r.coarse_fracture_frame) EXPECT_EQ(f, 2);
    if (cells == 3) {
      EXPECT_GT(sc.rim_added, 0u);  // the rim crosses B's edges: the transfer covers embed_rim's vertices too
    }
  }
}

TEST(AnimateRigid, WholeObjectMovesRigidlyAndNeverFractures) {
  const Scene sc = make_scene(3);
  const Motion motion = [](int, std::size_t t, glm::dvec3 x) {
    return rotation(0.5 * double(t), {0.2, -1, 0.3}) * x + glm::dvec3(0.1 * double(t), 2.0, 0.0);
  };
  const AnimationResult r = animate_pieces(sc.model, animate_model(sc, 4, motion), sc.tree, sc.pieces);
  expect_motion(sc, r, motion, 1e-9);
  for (std::int64_t f : r.coarse_fracture_frame) EXPECT_EQ(f, kNeverFractures);
}

TEST(AnimateRigid, RigidTransformsFormUsesPieceTransforms) {
  const Scene sc = make_scene(3);
  auto transform = [](int piece, std::size_t t) {
    glm::dmat4 m(1.0);
    if (piece == 1) {
      m = glm::dmat4(rotation(0.2 * double(t), {0, 0, 1}));
      m[3] = glm::dvec4(0.3 * double(t), 0.0, 0.1, 1.0);
    }
    return m;
  };
  const Motion motion = [&](int piece, std::size_t t, glm::dvec3 x) { return glm::dvec3(transform(piece, t) * glm::dvec4(x, 1.0)); };
  CoarseAnimation a = animate_model(sc, 5, motion);
  for (std::size_t t = 0; t < 5; ++t) a.piece_transforms.push_back({transform(0, t), transform(1, t)});
  const AnimationTransfer tr = build_transfer(sc.model, a, sc.tree, sc.pieces);
  EXPECT_EQ(tr.source, DeformationSource::kRigid);
  AnimationResult r;
  r.layout = tr.layout;
  for (std::size_t t = 0; t < 5; ++t) r.frames.push_back(transfer_frame(tr, a, t));
  expect_motion(sc, r, motion, 1e-9);
  EXPECT_THROW(transfer_frame(tr, a, 5), RunError);
}

TEST(AnimateAffine, AffineMotionReproducedExactly) {
  const Scene sc = make_scene(3);
  const glm::dmat3 M(1.2, 0.3, -0.1, 0.2, 0.8, 0.4, -0.3, 0.1, 1.5);
  const Motion motion = [&](int, std::size_t t, glm::dvec3 x) {
    const double s = double(t) / 3.0;
    return (glm::dmat3(1.0) * (1 - s) + M * s) * x + glm::dvec3(0.5, -1.0, 0.25) * s;
  };
  const AnimationResult r = animate_pieces(sc.model, animate_model(sc, 4, motion), sc.tree, sc.pieces);
  expect_motion(sc, r, motion, 1e-12);
}

// Piece 1 is sheared (zero displacement on the cut) from frame 1 and pulled away from frame 4.
// The shear gives the two pieces different affine maps on the cut, so a refined vertex off the
// coarse plane would be placed differently by each piece: the rule must keep them together.
Motion shear_then_pull() {
  return [](int piece, std::size_t t, glm::dvec3 x) {
    if (piece == 0) return x;
    const double shear = 0.3 * double(std::min<std::size_t>(t, 3));
    const double pull = t >= 4 ? 0.2 * double(t - 3) : 0.0;
    return x + glm::dvec3(pull, shear * (x.x - 1.0), 0.0);
  };
}

TEST(AnimateFractureTime, SharedVerticesTogetherUntilTheCoarseCopiesSeparate) {
  for (int cells : {2, 3}) {
    const Scene sc = make_scene(cells);
    const CoarseAnimation a = animate_model(sc, 7, shear_then_pull());
    const AnimationTransfer tr = build_transfer(sc.model, a, sc.tree, sc.pieces);
    for (std::int64_t f : tr.coarse_fracture_frame) EXPECT_EQ(f, 4);
    ASSERT_FALSE(tr.shared.empty());
    std::size_t raw_apart = 0;
    for (std::size_t t = 0; t < 7; ++t) {
      const std::vector<glm::dvec3> x = transfer_frame(tr, a, t);
      for (const SharedVertex& sv : tr.shared) {
        ASSERT_EQ(sv.pieces, (std::vector<int>{0, 1}));
        EXPECT_EQ(sv.pair_fracture[0], 4) << "vertex " << sv.vertex;
        const glm::dvec3 d = x[sv.slots[1]] - x[sv.slots[0]];
        if (t < 4) {
          EXPECT_EQ(x[sv.slots[0]], x[sv.slots[1]]) << "frame " << t << " vertex " << sv.vertex;
        } else {
          EXPECT_GT(glm::length(d), 0.19 * double(t - 3)) << "frame " << t << " vertex " << sv.vertex;
        }
        // What each piece alone would give (the terms without the rule): apart for the refined ones.
        if (t == 3 && sv.vertex >= 4 && sv.vertex < sc.refined.vertex_count()) {
          glm::dvec3 raw[2];
          const std::vector<glm::dvec3>& xs = a.frames[t];
          for (int k = 0; k < 2; ++k) {
            raw[k] = glm::dvec3(0.0);
            for (std::uint32_t i = tr.term_offsets[sv.slots[k]]; i < tr.term_offsets[sv.slots[k] + 1]; ++i) {
              const TransferTerm& term = tr.terms[i];
              const glm::dmat3 A = k == 0 ? glm::dmat3(1.0) : glm::dmat3(1, 0.9, 0, 0, 1, 0, 0, 0, 1);
              raw[k] += term.weight * (A * term.offset + xs[tr.anchors[term.anchor].x]);
            }
          }
          raw_apart += glm::length(raw[1] - raw[0]) > 1e-3;
        }
      }
    }
    EXPECT_GT(raw_apart, 0u);
  }
}

TEST(AnimateFractureTime, ExteriorVerticesFollowTheirPiece) {
  const Scene sc = make_scene(3);
  const Motion motion = shear_then_pull();
  const AnimationResult r = animate_pieces(sc.model, animate_model(sc, 7, motion), sc.tree, sc.pieces);
  // Away from the cut, each piece's motion is affine, so every vertex not shared follows it exactly.
  for (std::size_t t = 0; t < r.frames.size(); ++t)
    for (std::size_t p = 0; p < 2; ++p)
      for (std::size_t i = 0; i < r.layout.vertices[p].size(); ++i) {
        const std::uint32_t v = r.layout.vertices[p][i];
        if (sc.pieces.vertex_origin[v] >= 0 || std::abs(sc.pieces.positions[v].x - 1.0) < 1e-9) continue;
        EXPECT_LT(glm::length(r.frames[t][r.layout.offsets[p] + i] - motion(int(p), t, sc.pieces.positions[v])), 1e-12);
      }
  // After the fracture time, shared vertices follow their own piece exactly too.
  expect_motion(sc, AnimationResult{r.layout, {r.frames.begin() + 4, r.frames.end()}, {}, 24.0},
                [&](int p, std::size_t t, glm::dvec3 x) { return motion(p, t + 4, x); }, 1e-12);
}

TEST(AnimateSurface, PiecesInputMovedRigidlyWithoutTets) {
  // Two closed boxes as pre-fractured pieces: no tets, no transforms -> triangle gradients.
  std::vector<PieceInput> inputs;
  for (int p = 0; p < 2; ++p) {
    const TriangleSoup t = make_box({double(p), 0, 0}, {double(p) + 1, 1, 1}, 1);
    PieceInput in;
    in.name = "box" + std::to_string(p);
    in.positions = t.positions;
    in.triangles = t.triangles;
    for (std::uint32_t i = 0; i < t.triangles.size(); ++i) in.triangle_polygon.push_back(i / 2);
    inputs.push_back(in);
  }
  Scene sc;
  sc.model = build_pieces_model(inputs);
  ASSERT_EQ(sc.model.piece_count, 2);
  sc.exterior = box_soup({0, 0, 0}, {2, 1, 1}, 3);
  sc.refined = sc.model.surface;
  sc.tree = RefinementTree::identity(sc.refined.vertex_count());
  std::vector<SplitRequest> requests;
  for (std::uint32_t f = 0; f < sc.refined.face_count(); ++f) requests.push_back({SplitRequest::kFace, f, glm::vec3(0.2f, 0.3f, 0.5f)});
  apply_splits(sc.refined, sc.tree, requests);
  for (std::size_t v = sc.model.surface.vertex_count(); v < sc.refined.vertex_count(); ++v) sc.refined.positions[v].x += 0.05f;
  embed_and_build(sc);
  sc.vertex_piece.assign(sc.model.vertices.size(), -1);
  for (std::size_t f = 0; f < sc.model.hull.size(); ++f)
    for (int k = 0; k < 3; ++k) sc.vertex_piece[sc.model.hull[f][k]] = sc.model.hull_piece[f];
  for (std::size_t e = 0; e < sc.model.surface.copies.size(); ++e)
    sc.vertex_piece[sc.model.surface_copy_model_vertex[e]] = int(sc.model.surface.copies[e].x);
  const Motion motion = [](int piece, std::size_t t, glm::dvec3 x) {
    const glm::dvec3 shift = piece == 1 ? glm::dvec3(0.5 * double(t), 0, 0) : glm::dvec3(0.0);
    return rotation(0.4 * double(t), {1, 1, 0}) * x + shift;
  };
  const AnimationTransfer tr = build_transfer(sc.model, animate_model(sc, 4, motion), sc.tree, sc.pieces);
  EXPECT_EQ(tr.source, DeformationSource::kSurface);
  EXPECT_EQ(tr.identity_anchors, 0u);
  const AnimationResult r = animate_pieces(sc.model, animate_model(sc, 4, motion), sc.tree, sc.pieces);
  expect_motion(sc, r, motion, 1e-9);
}

TEST(AnimateErrors, MismatchedInputsAreRunErrors) {
  const Scene sc = make_scene(2, 1);
  CoarseAnimation a = animate_model(sc, 2, [](int, std::size_t, glm::dvec3 x) { return x; });
  EXPECT_THROW(build_transfer(sc.model, CoarseAnimation{}, sc.tree, sc.pieces), RunError);
  CoarseAnimation short_frame = a;
  short_frame.frames[1].pop_back();
  try {
    build_transfer(sc.model, short_frame, sc.tree, sc.pieces);
    ADD_FAILURE() << "no RunError";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("frame 1 has"), std::string::npos) << e.what();
  }
  RefinementTree short_tree = sc.tree;
  short_tree.parents.resize(4);
  short_tree.weights.resize(4);
  EXPECT_THROW(build_transfer(sc.model, a, short_tree, sc.pieces), RunError);
  CoarseAnimation bad_rigid = a;
  bad_rigid.piece_transforms.resize(1);
  EXPECT_THROW(build_transfer(sc.model, bad_rigid, sc.tree, sc.pieces), RunError);
}

TEST(AnimateFrames, WritesOneObjPerFrameWithEveryPiece) {
  const Scene sc = make_scene(3);
  const Motion motion = shear_then_pull();
  CoarseAnimation a = animate_model(sc, 3, motion);
  a.fps = 30.0;
  const AnimationResult r = animate_pieces(sc.model, a, sc.tree, sc.pieces);
  test::TempDir dir;
  write_frames(sc.pieces, r, dir.path());
  for (std::size_t t = 0; t < 3; ++t) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu.obj", t);
    const MeshSoup m = read_obj(dir.path() / "frames" / name);
    ASSERT_EQ(m.groups, (std::vector<std::string>{"piece_000", "piece_001"}));
    ASSERT_EQ(m.positions.size(), r.layout.slot_count());
    std::size_t triangles = 0;
    for (const auto& piece : sc.pieces.pieces) triangles += piece.triangles.size();
    ASSERT_EQ(m.triangles.size(), triangles);
    for (std::size_t s = 0; s < m.positions.size(); ++s) ASSERT_EQ(m.positions[s], r.frames[t][s]);  // bit for bit
    for (std::size_t i = 0; i < m.triangles.size(); ++i) {
      const std::uint32_t g = m.triangle_group[i];
      for (std::uint32_t v : m.triangles[i]) ASSERT_TRUE(v >= r.layout.offsets[g] && v < r.layout.offsets[g + 1]);
    }
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "frames" / "frame_0003.obj"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "frames" / "frames.mtl"));
  std::ifstream in(dir.path() / "frames" / "frame_0001.obj");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("# fracref frame 1 of 3, fps 30\nmtllib frames.mtl\no piece_000\n"), std::string::npos);
  EXPECT_NE(text.str().find("usemtl inside"), std::string::npos);
  // The streaming writer gives the same bytes.
  const std::filesystem::path other = dir.path() / "streamed";
  write_frames(sc.pieces, build_transfer(sc.model, a, sc.tree, sc.pieces), a, other);
  std::ifstream in2(other / "frames" / "frame_0001.obj");
  std::stringstream text2;
  text2 << in2.rdbuf();
  EXPECT_EQ(text.str(), text2.str());
}

}  // namespace
}  // namespace fracref
