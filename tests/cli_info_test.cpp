// `fracref info` as a user runs it: exact counts for accepted meshes, and for every malformed
// case one message on stderr naming the file (and the line) and exit code 2.
#include <gtest/gtest.h>

#include "cli_support.hpp"

using cli_test::run;
using cli_test::TempDir;

TEST(CliInfo, FinOfThreeTrianglesJson) {
  TempDir t;
  auto f = t.write("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  auto r = run("info " + f.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"vertices\": 5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"faces\": 3"), std::string::npos);
  EXPECT_NE(r.out.find("\"non_manifold_edges\": 1"), std::string::npos);
  EXPECT_NE(r.out.find("\"boundary_edges\": 6"), std::string::npos);
  EXPECT_NE(r.out.find("\"closed\": false"), std::string::npos);
}

TEST(CliInfo, ClosedTetrahedronAndQuadsAndCrlf) {
  TempDir t;
  auto tet = t.write("tet.off", "OFF\r\n4 4 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n0 0 1\r\n3 0 2 1\r\n3 0 1 3\r\n3 0 3 2\r\n3 1 2 3\r\n");
  auto r = run("info " + tet.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"closed\": true"), std::string::npos) << r.out;
  auto quad = t.write("quad.obj", "f 1 2 3 4\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n");
  r = run("info " + quad.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"faces\": 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"polygons_triangulated\": 1"), std::string::npos);
}

struct BadCase {
  const char* name;
  const char* text;
  const char* expect;  // a part of the message after the file name
};

TEST(CliInfo, EveryMalformedCaseExitsTwoNamingTheFile) {
  const BadCase cases[] = {
      {"nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", ":2:"},
      {"inf.obj", "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n", ":2:"},
      {"overflow.obj", "v 0 0 1e999\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1:"},
      {"fields.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1:"},
      {"text.obj", "v 0 zero 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1:"},
      {"comma.obj", "v 0,5 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", ":1:"},
      {"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 2 3\n", ":4:"},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", ":4:"},
      {"negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -7\n", ":4:"},
      {"repeat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 2\n", ":4:"},
      {"short.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", ":3:"},
      {"counts.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "counts.off"},
      {"truncated.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n\x01\x02", "truncated.ply"},
      {"empty.obj", "", "empty.obj"},
      {"mesh.xyz", "v 0 0 0\n", "mesh.xyz"},
  };
  TempDir t;
  for (const BadCase& c : cases) {
    auto f = t.write(c.name, c.text);
    auto r = run("info " + f.string());
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(f.string()), std::string::npos) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << c.name;
  }
  auto r = run("info " + (t.path / "missing.obj").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("missing.obj"), std::string::npos) << r.err;
}

TEST(CliInfo, HelpVersionAndUsageErrors) {
  auto r = run("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("fracref"), std::string::npos);
  r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* sub : {"info", "refine", "demo", "bench", "batch", "check"})
    EXPECT_NE(r.out.find(sub), std::string::npos) << sub;
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("frobnicate").code, 2);
  EXPECT_EQ(run("info").code, 2);
  EXPECT_EQ(run("refine x.json -o out --backend quantum").code, 2);
  EXPECT_EQ(run("refine x.json -o out --stop-after lunch").code, 2);
}
