// The MEDIT and TetGen readers: what they accept, and each malformed case's message.
#include <gtest/gtest.h>

#include "coarse/tet_readers.hpp"
#include "coarse_test_support.hpp"

namespace fracref {
namespace {
using test::input_error;

// Two tets sharing the face 1 2 3 (1-based), pieces 4 and 9; vertex 5 unused by tets.
const char* kMedit = R"(MeshVersionFormatted 2
# a comment
Dimension
3
Vertices
6
0 0 0 1
1 0 0 1
0 1 0 1
0 0 1 1
1 1 1 1
5 5 5 0
Tetrahedra 2
1 2 3 4 4
2 3 4 5 9
Triangles
1
1 2 3 7
Corners 1
6
Normals
1
0 0 1
End
)";

// The message without the file path in front.
std::string medit_error(const test::TempDir& dir, const std::string& text) {
  const auto p = dir.file("m.mesh", text);
  return input_error([&] { read_medit(p); }).substr(p.string().size());
}

TEST(CoarseReaders, MeditReadsVerticesTetsAndLabels) {
  const test::TempDir dir;
  const TetMesh m = read_medit(dir.file("m.mesh", kMedit));
  EXPECT_EQ(m.vertices.size(), 6u);
  EXPECT_EQ(m.vertices[4], glm::dvec3(1, 1, 1));
  EXPECT_EQ(m.tets, (std::vector<glm::uvec4>{{0, 1, 2, 3}, {1, 2, 3, 4}}));
  EXPECT_EQ(m.labels, (std::vector<std::int64_t>{4, 9}));
  EXPECT_EQ(m.tet_lines, (std::vector<std::size_t>{14, 15}));
  const CoarseModel model = load_tet_model(dir.path() / "m.mesh", {});
  EXPECT_EQ(model.piece_count, 2);
  EXPECT_EQ(model.surface.face_count(), 1u);
  EXPECT_EQ(model.hull.size(), 6u);
}

TEST(CoarseReadersErrors, MeditMalformed) {
  const test::TempDir dir;
  const std::string ok = kMedit;
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string s = ok;
    s.replace(s.find(from), from.size(), to);
    return medit_error(dir, s);
  };
  EXPECT_EQ(with("Vertices\n6", "Vertices\n7"), ":13: found 'Tetrahedra' after 6 of the 7 entries of section 'Vertices' (is the count too large?)");
  EXPECT_EQ(with("Vertices\n6", "Vertices\n5"),
            ":12: expected a section keyword, found '5' (more entries than the count of section 'Vertices' announced?)");
  EXPECT_EQ(with("2 3 4 5 9", "2 3 4 7 9"), ":15: tetrahedron index 7 is out of range (the file has 6 vertices; MEDIT indices start at 1)");
  EXPECT_EQ(with("2 3 4 5 9", "2 3 4 0 9"), ":15: tetrahedron index 0 is out of range (the file has 6 vertices; MEDIT indices start at 1)");
  EXPECT_EQ(with("0 1 0 1\n", "0 nan 0 1\n"), ":9: coordinate 'nan' is not finite");
  EXPECT_EQ(with("0 1 0 1\n", "0 1 0\n"), ":9: vertex needs 4 values (x y z ref), got 3");
  EXPECT_EQ(with("2 3 4 5 9", "2 3 4 5 -9"), ":15: tetrahedron reference (piece label) -9 is negative");
  EXPECT_EQ(with("2 3 4 5 9", "2 3 4 5 1.5"), ":15: tetrahedron reference '1.5' is not an integer");
  EXPECT_EQ(with("Tetrahedra 2", "Tetrahedra 3"), ":16: found 'Triangles' after 2 of the 3 entries of section 'Tetrahedra' (is the count too large?)");
  EXPECT_EQ(with("1 2 3 7", "1 2 9 7"), ":18: Triangles vertex index 9 is out of range (the file has 6 vertices; MEDIT indices start at 1)");
  EXPECT_EQ(with("Corners 1\n6", "Corners 1\n6 6"), ":20: Corners entry needs 1 values (1 numbers), got 2");
  EXPECT_EQ(with("End\n", ""), ":23: file ends without 'End'");
  EXPECT_EQ(with("End\n", "End\n1 2\n"), ":25: data after 'End'");
  EXPECT_EQ(with("Dimension\n3", "Dimension\n2"), ":4: Dimension 2 is not supported (only 3)");
  EXPECT_EQ(with("MeshVersionFormatted 2", "MeshVersion 2"), ":1: expected 'MeshVersionFormatted', found 'MeshVersion' (not a MEDIT .mesh file?)");
  EXPECT_EQ(with("Triangles\n1\n1 2 3 7", "Hexahedra\n0"), ":16: section 'Hexahedra' is not supported (only tetrahedra)");
  EXPECT_EQ(with("Triangles\n1\n1 2 3 7", "Pentagons\n0"), ":16: unknown section 'Pentagons'");
  EXPECT_EQ(with("Triangles\n1\n1 2 3 7", "Vertices\n0"), ":16: section 'Vertices' appears twice");
  EXPECT_EQ(medit_error(dir, "MeshVersionFormatted 1\nDimension 3\nTetrahedra 0\nEnd\n"),
            ":3: section 'Tetrahedra' comes before section 'Vertices' (its indices name vertices)");
  EXPECT_EQ(medit_error(dir, "MeshVersionFormatted 1\nDimension 3\nVertices 0\nEnd\n"),
            ":4: the mesh has no tetrahedra (no 'Tetrahedra' section, or its count is 0)");
  EXPECT_EQ(medit_error(dir, "MeshVersionFormatted 1\nDimension 3\nVertices -1\nEnd\n"), ":3: Vertices count '-1' is negative");
  EXPECT_EQ(input_error([&] { read_medit(dir.path() / "none.mesh"); }), (dir.path() / "none.mesh").string() + ": cannot open: no such file");
}

TEST(CoarseReadersErrors, MeditZeroVolumeTetNamesItsLine) {
  const test::TempDir dir;
  std::string s = kMedit;
  s.replace(s.find("1 1 1 1\n"), 8, "0.5 0.5 0 1\n");  // vertex 5 into the plane of 2 3 4
  const auto p = dir.file("flat.mesh", s);
  const std::string e = input_error([&] { load_tet_model(p, {}); });
  EXPECT_EQ(e.rfind(p.string() + ":15: tetrahedron has zero volume (its four vertices", 0), 0u) << e;
}

const char* kNode = "# points\n5 3 1 1\n1 0 0 0 0.5 0\n2 1 0 0 0.5 1\n3 0 1 0 0.5 1\n4 0 0 1 0.5 1\n5 1 1 1 0.5 0\n";
const char* kEle = "2 4 1\n1 1 2 3 4 3\n2 2 3 4 5 0.0  # region 0\n";

TEST(CoarseReaders, TetgenOneBasedWithRegions) {
  const test::TempDir dir;
  dir.file("b.node", kNode);
  dir.file("b.ele", kEle);
  for (const char* name : {"b", "b.node", "b.ele"}) {
    const TetMesh m = read_tetgen(dir.path() / name);
    EXPECT_EQ(m.file, (dir.path() / "b.ele").string());
    EXPECT_EQ(m.vertices.size(), 5u);
    EXPECT_EQ(m.tets, (std::vector<glm::uvec4>{{0, 1, 2, 3}, {1, 2, 3, 4}}));
    EXPECT_EQ(m.labels, (std::vector<std::int64_t>{3, 0}));
    EXPECT_EQ(m.tet_lines, (std::vector<std::size_t>{2, 3}));
  }
  const CoarseModel model = load_tet_model(dir.path() / "b.ele", {});
  EXPECT_EQ(model.piece_count, 2);
  EXPECT_EQ(model.surface.face_count(), 1u);
}

TEST(CoarseReaders, TetgenZeroBasedWithoutAttributes) {
  const test::TempDir dir;
  dir.file("z.node", "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n");
  dir.file("z.ele", "1 4 0\n0 0 1 2 3\n");
  const TetMesh m = read_tetgen(dir.path() / "z");
  EXPECT_EQ(m.tets, (std::vector<glm::uvec4>{{0, 1, 2, 3}}));
  EXPECT_EQ(m.labels, (std::vector<std::int64_t>{0}));
}

TEST(CoarseReadersErrors, TetgenMalformed) {
  const test::TempDir dir;
  const auto error = [&](const std::string& node, const std::string& ele, bool ele_file) {
    dir.file("t.node", node);
    dir.file("t.ele", ele);
    const std::string e = input_error([&] { read_tetgen(dir.path() / "t"); });
    return e.substr((dir.path() / (ele_file ? "t.ele" : "t.node")).string().size());
  };
  const std::string node = kNode, ele = kEle;
  EXPECT_EQ(error(node, "2 4 1\n1 1 2 3 4 3\n2 2 3 4 6 0\n", true),
            ":3: node index 6 is out of range (the .node file has 5 points numbered from 1)");
  EXPECT_EQ(error(node, "2 4 1\n1 1 2 3 4 3\n3 2 3 4 5 0\n", true), ":3: tetrahedron index 3 breaks the sequence (expected 2)");
  EXPECT_EQ(error(node, "2 10 1\n", true), ":1: 10 nodes per tetrahedron are not supported (only 4)");
  EXPECT_EQ(error(node, "2 4 2\n", true), ":1: 2 attributes per tetrahedron; expected 0 or 1 (the region = piece)");
  EXPECT_EQ(error(node, "2 4 1\n1 1 2 3 4 3.5\n", true), ":2: region attribute '3.5' is not an integer >= 0 (it is the piece label)");
  EXPECT_EQ(error(node, "3 4 1\n1 1 2 3 4 3\n2 2 3 4 5 0\n", true), ":3: file ends after 2 of the 3 tetrahedra");
  EXPECT_EQ(error(node, ele + "3 1 2 3 4 0\n", true), ":4: data after the 2 tetrahedra announced in the header");
  EXPECT_EQ(error("5 3 1 1\n2 0 0 0 0.5 0\n", ele, false), ":2: the first point index is 2; TetGen numbers from 0 or 1");
  EXPECT_EQ(error("5 2 0 0\n", ele, false), ":1: dimension 2 is not supported (only 3)");
  EXPECT_EQ(error("5 3 1 1\n1 0 0 0 0\n", ele, false), ":2: point needs 6 values (index x y z, 1 attributes, 1 marker), got 5");
  EXPECT_EQ(error("2 3 0 0\n1 0 0 0\n2 0 inf 0\n", ele, false), ":3: coordinate 'inf' is not finite");
  dir.file("lonely.ele", ele);
  EXPECT_EQ(input_error([&] { read_tetgen(dir.path() / "lonely.ele"); }),
            (dir.path() / "lonely.node").string() + ": cannot open: no such file");
}

}  // namespace
}  // namespace fracref
