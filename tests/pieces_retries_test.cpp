// What build_pieces changes between attempts (pieces/retries.hpp): pushes of poking vertices
// and the futile-push rule, flaps, traces along the normal, contractions after crossing traces
// and folds.
#include <gtest/gtest.h>

#include "pieces/retries.hpp"

namespace fracref {
namespace {

using namespace pieces_detail;
using Contraction = std::pair<std::uint32_t, std::uint32_t>;

// Vertex 7 poking out by `depth`, with room `limit` and neighbours 3 (nearest) and 9.
PokingOut poke(double depth, double limit = 1.0) {
  PokingOut::Vertex v{depth, limit, glm::dvec3(1.0, 2.0, 3.0), {3, 9}, glm::dvec3(0.0, 0.0, -1.0)};
  return PokingOut({{7, v}});
}

TEST(PiecesRetries, APokeThatGetsShallowerKeepsBeingPushed) {
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(poke(0.01), why));
  ASSERT_TRUE(r.next(poke(0.005), why));  // half as deep: the push works
  ASSERT_TRUE(r.next(poke(0.0037), why));  // 0.74 of the last depth: still shrinking enough
  EXPECT_TRUE(r.contractions.empty());
  ASSERT_EQ(r.pushed.count(7), 1u);
  EXPECT_DOUBLE_EQ(r.pushed.at(7).distance, kPushFactor * (0.01 + 0.005 + 0.0037));
  EXPECT_DOUBLE_EQ(r.pushed.at(7).last_depth, 0.0037);
  EXPECT_EQ(r.pushed.at(7).direction, glm::dvec3(0.0, 0.0, -1.0));
  EXPECT_EQ(r.push_rounds, 3u);
}

TEST(PiecesRetries, AFutilePushContractsTheVertexAtOnce) {
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(poke(0.01), why));
  EXPECT_TRUE(r.contractions.empty());
  // The poke after the push is kFutilePush of the one before, well inside the vertex's room: the
  // push is not working, so the vertex goes into its nearest neighbour instead of a second push.
  ASSERT_TRUE(r.next(poke(kFutilePush * 0.01), why));
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{7, 3}}));
  EXPECT_EQ(r.pushed.count(7), 0u);
  EXPECT_EQ(r.push_rounds, 2u);
}

TEST(PiecesRetries, APokeThatGrowsIsFutileToo) {
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(poke(0.01), why));
  ASSERT_TRUE(r.next(poke(0.02), why));
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{7, 3}}));
}

TEST(PiecesRetries, TheFirstPushIsNeverFutile) {
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(poke(0.5), why));  // deep, but within the limit
  EXPECT_TRUE(r.contractions.empty());
  EXPECT_DOUBLE_EQ(r.pushed.at(7).distance, kPushFactor * 0.5);
}

TEST(PiecesRetries, APushPastTheLimitContracts) {
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(poke(0.9, 1.0), why));  // 1.25 * 0.9 > 1
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{7, 3}}));
  EXPECT_EQ(r.pushed.count(7), 0u);
}

TEST(PiecesRetries, PushRoundsAreCapped) {
  Retries r;
  std::string why;
  double depth = 1e-3;
  for (std::size_t round = 0; round < kMaxPushRounds; ++round, depth *= 0.5) {
    ASSERT_TRUE(r.next(poke(depth, 100.0), why));
    ASSERT_TRUE(r.contractions.empty()) << "round " << round;
  }
  ASSERT_TRUE(r.next(poke(depth, 100.0), why));
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{7, 3}}));
}

TEST(PiecesRetries, AfterTheNearestNeighbourTheNextAndThenAnErrorNamingTheVertex) {
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(poke(0.9), why));
  ASSERT_TRUE(r.next(poke(0.9), why));
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{7, 3}, {7, 9}}));
  EXPECT_FALSE(r.next(poke(0.9), why));
  EXPECT_NE(why.find("vertex 7 at"), std::string::npos) << why;
  EXPECT_NE(why.find("poke out of the exterior"), std::string::npos) << why;
}

TEST(PiecesRetries, PokingOutDescribesTheDeepestVertex) {
  PokingOut::Vertex a{0.1, 1.0, glm::dvec3(0.0), {}, glm::dvec3(0.0)};
  PokingOut::Vertex b{0.3, 1.0, glm::dvec3(0.0), {}, glm::dvec3(0.0)};
  const std::string d = PokingOut({{4, a}, {5, b}}).describe();
  EXPECT_NE(d.find("vertex 5 at"), std::string::npos) << d;
  EXPECT_NE(d.find("1 more vertices"), std::string::npos) << d;
}

UntriangulatedFaces::Face face(std::uint32_t id, bool flap) {
  return {"face " + std::to_string(id) + " cannot be triangulated", id, flap, glm::uvec2(10, 11)};
}

TEST(PiecesRetries, AFlapIsLeftOutOnce) {
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(UntriangulatedFaces({face(2, true)}), why));
  EXPECT_EQ(r.left_out, (std::vector<std::uint32_t>{2}));
  EXPECT_FALSE(r.next(UntriangulatedFaces({face(2, true)}), why));
  EXPECT_EQ(why, "face 2 cannot be triangulated");
}

TEST(PiecesRetries, AFaceGoesAlongItsNormalThenItsEdgeIsContracted) {
  Retries r;
  ASSERT_TRUE(r.next(face(4, false)));
  EXPECT_EQ(r.along_normal.count(4), 1u);
  ASSERT_TRUE(r.next(face(4, false)));  // neither plane works: the edge goes, one way then the other
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{11, 10}}));
  ASSERT_TRUE(r.next(face(4, false)));
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{11, 10}, {10, 11}}));
  EXPECT_FALSE(r.next(face(4, false)));
}

TEST(PiecesRetries, APushSendsAFaceBackToTheUsualPlane) {
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(face(4, false)));
  ASSERT_TRUE(r.next(poke(0.01), why));  // S moved since the face was sent along its normal
  ASSERT_TRUE(r.next(face(4, false)));
  EXPECT_EQ(r.along_normal.count(4), 0u);
  EXPECT_TRUE(r.contractions.empty());
}

TEST(PiecesRetries, CrossingTracesOfAZigzagContractTheSharedVertexIntoItsNearerNeighbour) {
  const std::vector<glm::dvec3> x{{0, 0, 0}, {1, 0, 0}, {0, 0.5, 0}, {5, 5, 5}, {6, 5, 5}, {5, 7, 5}, {9, 9, 9}};
  Retries r;
  // Edges 1-0 and 0-2 share vertex 0; 2 is nearer to it than 1.
  ASSERT_TRUE(r.next(TracesCross("cross", {{glm::uvec2(1, 0), glm::uvec2(0, 2)}}), x));
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{0, 2}}));
  ASSERT_TRUE(r.next(TracesCross("cross", {{glm::uvec2(1, 0), glm::uvec2(0, 2)}}), x));
  EXPECT_EQ(r.contractions.back(), (Contraction{0, 1}));
  EXPECT_FALSE(r.next(TracesCross("cross", {{glm::uvec2(1, 0), glm::uvec2(0, 2)}}), x));
  // A zigzag at vertex 3 (edges 3-5 and 3-4): 3 goes into its nearer neighbour, 4.
  ASSERT_TRUE(r.next(TracesCross("cross", {{glm::uvec2(3, 5), glm::uvec2(3, 4)}}), x));
  EXPECT_EQ(r.contractions.back(), (Contraction{3, 4}));
  // Disjoint edges 5-6 and 3-4: the shorter edge's second end into its first.
  ASSERT_TRUE(r.next(TracesCross("cross", {{glm::uvec2(5, 6), glm::uvec2(3, 4)}}), x));
  EXPECT_EQ(r.contractions.back(), (Contraction{4, 3}));
}

TEST(PiecesRetries, AFoldContractsTheShortestEdgeThenRelaxes) {
  std::map<std::uint32_t, Folded::Vertex> v;
  v[1] = {glm::dvec3(0.0), 2, 0.5};
  v[5] = {glm::dvec3(0.0), 6, 0.1};
  const Folded folded("faces 8 and 9 cross", v);
  Retries r;
  std::string why;
  ASSERT_TRUE(r.next(folded, why));
  EXPECT_EQ(r.contractions, (std::vector<Contraction>{{5, 6}}));
  ASSERT_TRUE(r.next(folded, why));
  EXPECT_EQ(r.contractions.back(), (Contraction{1, 2}));
  for (int step = 0; step < 4; ++step) ASSERT_TRUE(r.next(folded, why)) << step;  // 4 * 0.25: all the way
  EXPECT_DOUBLE_EQ(r.relaxed.at(1), 1.0);
  EXPECT_DOUBLE_EQ(r.relaxed.at(5), 1.0);
  EXPECT_FALSE(r.next(folded, why));
  EXPECT_NE(why.find("faces 8 and 9 cross; still after moving fracture surface vertex"), std::string::npos) << why;
}

}  // namespace
}  // namespace fracref
