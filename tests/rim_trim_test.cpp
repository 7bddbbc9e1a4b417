// S trimmed to B (rim/trim_to_exterior.hpp), through embed_rim on a unit box: a cone of S whose
// rim runs around the box's walls and whose apex sticks out through the top is cut where it
// leaves B (a new rim on the top face, every new rim edge in one B triangle; the box is symmetric,
// so the cone's edges through the top's diagonal cross it exactly at a B edge), and a cone inside
// B is left as it was.
#include <gtest/gtest.h>

#include <algorithm>

#include "geom/bvh.hpp"
#include "geom/shapes.hpp"
#include "rim/rim_on_b.hpp"
#include "rim/trim_to_exterior.hpp"
#include "surface/fracture_surface.hpp"
#include "pieces_test_support.hpp"

namespace fracref {
namespace {

rim::ExteriorMesh unit_box() {
  const TriangleSoup t = make_box({0, 0, 0}, {1, 1, 1}, 1);
  MeshSoup soup;
  soup.positions = t.positions;
  soup.triangles = t.triangles;
  return rim::make_exterior_mesh(soup);
}

// A fan from `apex` over a loop of eight rim points around the box's walls at height z.
FractureSurface cone(const glm::vec3& apex, float z = 0.4f) {
  const std::vector<glm::vec3> loop = {{0, 0.3f, z}, {0.3f, 0, z}, {0.7f, 0, z}, {1, 0.3f, z},
                                       {1, 0.7f, z}, {0.7f, 1, z}, {0.3f, 1, z}, {0, 0.7f, z}};
  std::vector<glm::vec4> positions;
  for (const glm::vec3& p : loop) positions.emplace_back(p, 1.0f);
  positions.emplace_back(apex, 1.0f);
  std::vector<glm::uvec4> faces;
  for (std::uint32_t i = 0; i < loop.size(); ++i) faces.push_back({8u, i, (i + 1) % 8u, 0u});
  return make_fracture_surface(positions, faces, std::vector<glm::ivec2>(faces.size(), glm::ivec2(1, 0)), 2);
}

// The cone with its apex outside B, through embed_rim: trimmed to B.
void expect_trimmed(const glm::vec3& apex, float z = 0.4f) {
  SCOPED_TRACE("apex (" + std::to_string(apex.x) + ", " + std::to_string(apex.y) + ", " + std::to_string(apex.z) + "), rim at " +
               std::to_string(z));
  const rim::ExteriorMesh m = unit_box();
  FractureSurface s = cone(apex, z);
  const rim::Embedding e = rim::embed_rim(s, m);
  EXPECT_EQ(validate(s), "");
  EXPECT_GT(e.trim.cut_faces, 0u);
  EXPECT_GT(e.trim.new_vertices, 0u);
  EXPECT_EQ(rim::find_unembedded_rim(s, m, e.rim), "");
  // Every vertex S still uses is inside B or on it (a rim vertex, at its location).
  std::vector<char> used(s.positions.size(), 0);
  for (const glm::uvec4& f : s.faces) used[f.x] = used[f.y] = used[f.z] = 1;
  EXPECT_FALSE(used[8]);  // the apex is cut away
  int on_top = 0;
  for (std::uint32_t v = 0; v < s.positions.size(); ++v) {
    if (!used[v]) continue;
    if (e.rim.on_b[v]) {
      EXPECT_LT(std::sqrt(closest_point(m.bvh, e.rim.at[v].point).squared_distance), 1e-12) << v;
      on_top += e.rim.at[v].point.z > 1.0 - 1e-12;
    } else {
      EXPECT_TRUE(point_in_mesh(m.bvh, glm::dvec3(glm::vec3(s.positions[v])))) << v;
    }
  }
  EXPECT_GE(on_top, 3);  // the new rim: a loop on the top face
  // The new vertices record their parents: 2-parent points on S edges, 3-parent inside faces.
  for (const rim::EmbeddedVertex& a : e.added) {
    EXPECT_NEAR(a.weights.x + a.weights.y + a.weights.z, 1.0, 1e-9);
    EXPECT_GE(std::min({a.weights.x, a.weights.y, a.weights.z}), 0.0);
  }
}

TEST(RimTrim, AConeThroughTheTopIsCutWhereItLeavesB) { expect_trimmed({0.5f, 0.5f, 1.4f}); }

// Off the box's symmetry: the top's diagonal crosses the insides of S's faces.
TEST(RimTrim, AnOffCentreConeIsCutAlongTheTopsDiagonalToo) { expect_trimmed({0.43f, 0.58f, 1.35f}); }

// Apexes over the whole top (some over its diagonal, some near its sides), rims at many heights.
TEST(RimTrim, ConesThroughTheTopAtManyPlacesAreTrimmed) {
  std::uint32_t state = 12345u;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (int i = 0; i < 60; ++i) {
    const glm::vec3 apex(0.05f + 0.9f * next(), 0.05f + 0.9f * next(), 1.02f + 1.5f * next());
    expect_trimmed(apex, 0.1f + 0.8f * next());
    if (HasFailure()) break;
  }
}

// A concave B: the L-shaped prism of unit cells (0,0), (1,0), (0,1) in x, y, z in [0, 1]. A fan
// from an apex in the notch (outside B) over a loop around the L's walls, two of the loop's points
// on the notch's walls: the faces into the notch are cut where they cross its walls, the one
// between the notch's walls is dropped whole.
TEST(RimTrim, AFanIntoAConcaveNotchIsCutAtTheNotchsWalls) {
  const rim::ExteriorMesh m =
      rim::make_exterior_mesh(pieces_test::voxel_surface({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1.0));
  const float z = 0.4f;
  const std::vector<glm::vec3> loop = {{0.5f, 0, z}, {1.5f, 0, z}, {2, 0.5f, z}, {1.6f, 1, z},
                                       {1, 1.6f, z}, {0.5f, 2, z}, {0, 1.5f, z}, {0, 0.5f, z}};
  std::vector<glm::vec4> positions;
  for (const glm::vec3& p : loop) positions.emplace_back(p, 1.0f);
  positions.emplace_back(1.45f, 1.55f, 0.47f, 1.0f);
  std::vector<glm::uvec4> faces;
  for (std::uint32_t i = 0; i < loop.size(); ++i) faces.push_back({8u, i, (i + 1) % 8u, 0u});
  FractureSurface s = make_fracture_surface(positions, faces, std::vector<glm::ivec2>(faces.size(), glm::ivec2(1, 0)), 2);
  const rim::Embedding e = rim::embed_rim(s, m);
  EXPECT_EQ(validate(s), "");
  EXPECT_GT(e.trim.cut_faces, 0u);
  EXPECT_GT(e.trim.removed_faces, 0u);
  EXPECT_EQ(rim::find_unembedded_rim(s, m, e.rim), "");
  std::vector<char> used(s.positions.size(), 0);
  for (const glm::uvec4& f : s.faces) used[f.x] = used[f.y] = used[f.z] = 1;
  EXPECT_FALSE(used[8]);
  for (std::uint32_t v = 0; v < s.positions.size(); ++v) {
    if (!used[v]) continue;
    if (e.rim.on_b[v]) EXPECT_LT(std::sqrt(closest_point(m.bvh, e.rim.at[v].point).squared_distance), 1e-12) << v;
    else EXPECT_TRUE(point_in_mesh(m.bvh, glm::dvec3(glm::vec3(s.positions[v])))) << v;
  }
  // No face of S crosses into the notch: every face's centroid is inside B.
  for (const glm::uvec4& f : s.faces) {
    glm::dvec3 c(0.0);
    for (int k = 0; k < 3; ++k) c += (e.rim.on_b[f[k]] ? e.rim.at[f[k]].point : glm::dvec3(glm::vec3(s.positions[f[k]]))) / 3.0;
    EXPECT_TRUE(point_in_mesh(m.bvh, c)) << f.x << " " << f.y << " " << f.z;
  }
}

TEST(RimTrim, AConeInsideBIsLeftAsItWas) {
  const rim::ExteriorMesh m = unit_box();
  FractureSurface s = cone({0.5f, 0.5f, 0.8f}, 0.4f);
  const rim::Embedding e = rim::embed_rim(s, m);
  EXPECT_EQ(validate(s), "");
  EXPECT_EQ(e.trim.cut_faces, 0u);
  EXPECT_EQ(e.trim.removed_faces, 0u);
  EXPECT_EQ(e.trim.new_vertices, 0u);
  EXPECT_EQ(rim::find_unembedded_rim(s, m, e.rim), "");
}

}  // namespace
}  // namespace fracref
