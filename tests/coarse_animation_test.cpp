// Coarse animation input: per-frame files with backward remeshing (parent map), rigid per-piece
// transforms, and their errors.
#include <gtest/gtest.h>

#include "coarse/animation.hpp"
#include "coarse_test_support.hpp"

namespace fracref {
namespace {
using test::input_error;

// Two tets that share a face in material space, the upper one through its own copies 5, 6, 7 of
// the face's vertices 0, 1, 2: the last frame's topology after the simulator split them.
CoarseModel split_pair() {
  TetMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}, {0.2, 0.2, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.tets = {{0, 1, 2, 3}, {5, 6, 7, 4}};
  mesh.labels = {0, 1};
  return build_tet_model(mesh, nullptr);
}

glm::dvec3 frame_point(int frame, int v) { return {v, frame, 0.25 * v}; }

std::string frame_text(int frame, int vertices) {
  std::string s = "# frame " + std::to_string(frame) + "\n";
  for (int v = 0; v < vertices; ++v) {
    const glm::dvec3 p = frame_point(frame, v);
    s += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  }
  return s;
}

TEST(CoarseAnimation, ModelOfTheSplitPair) {
  const CoarseModel m = split_pair();
  EXPECT_EQ(m.vertices.size(), 8u);
  EXPECT_EQ(m.surface.face_count(), 1u);
  EXPECT_EQ(m.piece_count, 2);
  EXPECT_EQ(validate(m.surface), "");
}

TEST(CoarseAnimation, FramesWithGrowingVertexCountAndParentMap) {
  const test::TempDir dir;
  dir.file("frames/frame_0010.txt", frame_text(0, 5));
  dir.file("frames/frame_0011.txt", frame_text(1, 6));
  dir.file("frames/frame_0012.txt", frame_text(2, 8));
  const auto parents = dir.file("parents.txt", "# v parent\n5 0\n7 6\n6 1\n");
  const CoarseAnimation a = load_frames(dir.path() / "frames/frame_{:04}.txt", 10, 3, 30.0, parents, split_pair());
  EXPECT_EQ(a.fps, 30.0);
  ASSERT_EQ(a.frames.size(), 3u);
  EXPECT_EQ(a.file_vertex_counts, (std::vector<std::size_t>{5, 6, 8}));
  for (const auto& f : a.frames) EXPECT_EQ(f.size(), 8u);
  // Frame 0 has vertices 0..4: 5 -> 0, 6 -> 1, 7 -> 6 -> 1.
  EXPECT_EQ(a.frames[0][4], frame_point(0, 4));
  EXPECT_EQ(a.frames[0][5], frame_point(0, 0));
  EXPECT_EQ(a.frames[0][6], frame_point(0, 1));
  EXPECT_EQ(a.frames[0][7], frame_point(0, 1));
  // Frame 1 has 0..5.
  EXPECT_EQ(a.frames[1][5], frame_point(1, 5));
  EXPECT_EQ(a.frames[1][6], frame_point(1, 1));
  EXPECT_EQ(a.frames[1][7], frame_point(1, 1));
  for (int v = 0; v < 8; ++v) EXPECT_EQ(a.frames[2][v], frame_point(2, v));
}

TEST(CoarseAnimation, MeshFramesAndPlainPattern) {
  const test::TempDir dir;
  std::string obj;
  for (int v = 0; v < 8; ++v) obj += "v " + std::to_string(v) + " 1 2\n";
  dir.file("f3.obj", obj + "f 1 2 3\n");
  const CoarseAnimation a = load_frames(dir.path() / "f{}.obj", 3, 1, 24.0, {}, split_pair());
  ASSERT_EQ(a.frames.size(), 1u);
  EXPECT_EQ(a.frames[0][7], glm::dvec3(7, 1, 2));
  EXPECT_EQ(frame_file("a/b_{:03}.txt", 7), std::filesystem::path("a/b_007.txt"));
  EXPECT_EQ(frame_file("b_{}.txt", 1234), std::filesystem::path("b_1234.txt"));
}

TEST(CoarseAnimationErrors, FrameFiles) {
  const test::TempDir dir;
  const CoarseModel m = split_pair();
  const auto pattern = dir.path() / "f_{}.txt";
  const auto f0 = dir.file("f_0.txt", frame_text(0, 5)).string();
  EXPECT_EQ(input_error([&] { load_frames(pattern, 0, 1, 24, {}, m); }),
            f0 + ":6: the frame has 5 vertices, the model has 8 (no parent map is given)");
  const auto f1 = dir.file("f_1.txt", frame_text(1, 9)).string();
  EXPECT_EQ(input_error([&] { load_frames(pattern, 1, 1, 24, {}, m); }), f1 + ":10: the frame has more vertices than the model's 8");
  const auto f2 = dir.file("f_2.txt", "0 0 0\nnan 1 1\n").string();
  EXPECT_EQ(input_error([&] { load_frames(pattern, 2, 1, 24, {}, m); }), f2 + ":2: coordinate 'nan' is not finite");
  const auto f3 = dir.file("f_3.txt", "0 0\n").string();
  EXPECT_EQ(input_error([&] { load_frames(pattern, 3, 1, 24, {}, m); }), f3 + ":1: vertex needs 3 values (x y z), got 2");
  EXPECT_EQ(input_error([&] { load_frames(pattern, 4, 1, 24, {}, m); }), (dir.path() / "f_4.txt").string() + ": cannot open: no such file");
  EXPECT_EQ(input_error([&] { load_frames(dir.path() / "f.txt", 0, 1, 24, {}, m); }),
            (dir.path() / "f.txt").string() + ": a frame pattern needs exactly one '{}' or '{:0N}' field (N in 1..12) and no other brace");
  EXPECT_EQ(input_error([&] { load_frames(pattern, 0, 0, 24, {}, m); }), pattern.string() + ": frame count 0 must be at least 1");
  EXPECT_EQ(input_error([&] { load_frames(pattern, 0, 1, 0, {}, m); }), pattern.string() + ": fps must be a positive number");
}

TEST(CoarseAnimationErrors, ParentMaps) {
  const test::TempDir dir;
  const CoarseModel m = split_pair();
  dir.file("f_0.txt", frame_text(0, 5));
  dir.file("f_1.txt", frame_text(1, 6));
  const auto f2 = dir.file("f_2.txt", frame_text(2, 8)).string();
  const auto pattern = dir.path() / "f_{}.txt";
  const auto run = [&](const std::string& map, std::int64_t first = 0, std::int64_t count = 3) {
    const auto p = dir.file("p.txt", map);
    return input_error([&] { load_frames(pattern, first, count, 24, p, m); });
  };
  const std::string p = (dir.path() / "p.txt").string();
  EXPECT_EQ(run("5 6\n6 5\n7 1\n"), p + ":1: the parent map has a cycle through vertex 5");
  EXPECT_EQ(run("5 8\n"), p + ":1: parent 8 is out of range (the model has 8 vertices; ids start at 0)");
  EXPECT_EQ(run("-1 2\n"), p + ":1: vertex -1 is out of range (the model has 8 vertices; ids start at 0)");
  EXPECT_EQ(run("5 5\n"), p + ":1: vertex 5 is its own parent");
  EXPECT_EQ(run("5 0\n5 1\n"), p + ":2: vertex 5 already has a parent (line 1)");
  EXPECT_EQ(run("5 0 1\n"), p + ":1: parent map entry needs 2 values (v parent), got 3");
  EXPECT_EQ(run("5 7\n6 1\n7 2\n"), p + ":1: parent 7 of vertex 5 is not in " + (dir.path() / "f_1.txt").string() +
                                         " (6 vertices), the first frame that has vertex 5");
  EXPECT_EQ(run("5 0\n6 1\n"), (dir.path() / "f_0.txt").string() + ": vertex 7 is missing (the frame has 5 vertices) and " + p +
                                   " gives it no parent");
  EXPECT_EQ(run("5 0\n", 0, 2), (dir.path() / "f_1.txt").string() +
                                    ":7: the frame has 6 vertices, the model has 8 (the last frame must have the model's topology)");
  dir.file("f_3.txt", frame_text(3, 5));
  dir.file("f_4.txt", frame_text(4, 8));
  EXPECT_EQ(run("5 0\n", 2, 3), (dir.path() / "f_3.txt").string() + ":6: the frame has 5 vertices, fewer than the 8 of " + f2 +
                                    " (backward remeshing only adds vertices)");
}

const char* kIdentity = "1 0 0 0  0 1 0 0  0 0 1 0";

TEST(CoarseAnimation, RigidTransformsOfPieces) {
  const test::TempDir dir;
  PieceInput a, b;
  a.name = "a", b.name = "b";
  a.file = b.file = "mem";
  for (int k = 0; k < 8; ++k) {
    a.positions.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    b.positions.emplace_back(1 + (k & 1), (k >> 1) & 1, (k >> 2) & 1);
  }
  const std::array<std::uint32_t, 3> tris[12] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                                 {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  a.triangles.assign(tris, tris + 12);
  b.triangles = a.triangles;
  const CoarseModel m = build_pieces_model({a, b});
  ASSERT_EQ(m.surface.face_count(), 2u);
  const auto t = dir.file("rigid.txt", std::string("# frame piece R|t rows\n1 1 1 0 0 1  0 1 0 0  0 0 1 0\n0 0 ") + kIdentity +
                                           "\n0 1 " + kIdentity + "\n1 0 0 -1 0 0  1 0 0 0  0 0 1 0.5\n");
  const CoarseAnimation anim = load_rigid(t, 12.0, m);
  EXPECT_EQ(anim.fps, 12.0);
  ASSERT_EQ(anim.frames.size(), 2u);
  ASSERT_EQ(anim.piece_transforms.size(), 2u);
  EXPECT_EQ(anim.frames[0], m.vertices);
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    const glm::dvec3 x = m.vertices[v];
    const glm::dvec3 expect = v < 8 ? glm::dvec3(-x.y, x.x, x.z + 0.5) : x + glm::dvec3(1, 0, 0);
    EXPECT_EQ(anim.frames[1][v], expect) << v;
  }
}

TEST(CoarseAnimationErrors, RigidTransforms) {
  const test::TempDir dir;
  const CoarseModel m = build_tet_model(test::kuhn_box(1, 1, 2, [](glm::dvec3 c) { return c.z < 1 ? 0 : 1; }), nullptr);
  const std::string id = kIdentity;
  const auto run = [&](const std::string& text) {
    const auto p = dir.file("t.txt", text);
    return input_error([&] { load_rigid(p, 24, m); }).substr(p.string().size());
  };
  EXPECT_EQ(run("0 0 " + id + "\n0 1 " + id + "\n1 0 " + id + "\n"),
            ": frame 1 has no transform for piece 1 (frames run from 0 to 1, every piece in every frame)");
  EXPECT_EQ(run("0 0 " + id + "\n0 0 " + id + "\n"), ":2: frame 0 piece 0 is already given on line 1");
  EXPECT_EQ(run("1 0 " + id + "\n0 0 " + id + "\n0 0 " + id + "\n1 0 " + id + "\n"),
            ":3: frame 0 piece 0 is already given on line 2");
  // One line with a far frame number names the first missing pair without a table of 1e8 frames
  // (it took gigabytes).
  EXPECT_EQ(run("100000000 0 " + id + "\n"),
            ": frame 0 has no transform for piece 0 (frames run from 0 to 100000000, every piece in every frame)");
  EXPECT_EQ(run("0 2 " + id + "\n"), ":1: piece 2 is out of range (the model has 2 pieces)");
  EXPECT_EQ(run("0 0 2 0 0 0  0 2 0 0  0 0 2 0\n"),
            ":1: the 3x3 part is not a rotation (R^T R differs from the identity by 3.000000; scaling and shear are not rigid)");
  EXPECT_EQ(run("0 0 -1 0 0 0  0 1 0 0  0 0 1 0\n"), ":1: the 3x3 part is a reflection (determinant < 0), not a rotation");
  EXPECT_EQ(run("0 0 1 0 0\n"), ":1: transform needs 14 values (frame piece r00 r01 r02 t0 r10 r11 r12 t1 r20 r21 r22 t2), got 5");
  EXPECT_EQ(run("0 0 " + id + "\n0 1 " + id + "\n1 0 " + id + "\n1 1 1 0 0 0  0 1 0 0  0 0 1 0.5\n"),
            ":4: vertex 4 is shared by pieces 0 ('label 0') and 1 ('label 1'), which move differently in frame 1; in the rigid "
            "form every piece must own its vertices (duplicate them in the model, or give per-frame positions)");
  // Identical transforms of the pieces that share vertices are fine.
  const auto ok = dir.file("ok.txt", "0 0 " + id + "\n0 1 " + id + "\n1 0 1 0 0 3  0 1 0 0  0 0 1 0\n1 1 1 0 0 3  0 1 0 0  0 0 1 0\n");
  const CoarseAnimation anim = load_rigid(ok, 24, m);
  EXPECT_EQ(anim.frames[1][4], m.vertices[4] + glm::dvec3(3, 0, 0));
}

}  // namespace
}  // namespace fracref
