#pragma once
// A small two-piece cube scene shared by the end-to-end tests: a unit cube exterior (OBJ) and a
// MEDIT tet mesh of it with a piece label per tetrahedron.
#include <sstream>
#include <string>

namespace test_scenes {

/// A unit cube of n^3 cells, 6 tets each, labelled 0 below z = 0.5 and 1 above (MEDIT).
inline std::string cube_mesh(int n) {
  std::ostringstream v, t;
  auto id = [n](int i, int j, int k) { return 1 + i + (n + 1) * (j + (n + 1) * k); };
  int nv = 0, nt = 0;
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i, ++nv) v << double(i) / n << " " << double(j) / n << " " << double(k) / n << " 0\n";
  const int pairs[6][2] = {{1, 3}, {3, 2}, {2, 6}, {6, 4}, {4, 5}, {5, 1}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (auto& p : pairs) {
          auto c = [&](int q) { return id(i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1)); };
          t << c(0) << " " << c(p[0]) << " " << c(p[1]) << " " << c(7) << " " << (2 * k < n ? 0 : 1) << "\n";
          ++nt;
        }
  return "MeshVersionFormatted 2\nDimension 3\nVertices\n" + std::to_string(nv) + "\n" + v.str() + "Tetrahedra\n" +
         std::to_string(nt) + "\n" + t.str() + "End\n";
}

/// The unit cube [0, 1]^3, 12 triangles wound outward.
inline const char* const kCubeObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
    "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n";

}  // namespace test_scenes
