#pragma once
// Small inputs shared by the coarse tests: boxes of Kuhn-split cubes, temp folders, files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "coarse/coarse_model.hpp"
#include "util/error.hpp"

namespace fracref::test {

/// A box of nx*ny*nz unit cubes, each split into the 6 tets of the Kuhn triangulation around its
/// diagonal (conforming across cubes), positively oriented. `label(cube center)` gives each label.
inline TetMesh kuhn_box(int nx, int ny, int nz, const std::function<std::int64_t(glm::dvec3)>& label) {
  TetMesh mesh;
  auto id = [&](int i, int j, int k) { return std::uint32_t(i + (nx + 1) * (j + (ny + 1) * k)); };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) mesh.vertices.emplace_back(i, j, k);
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : perms) {
          glm::ivec3 c(i, j, k);
          glm::uvec4 tet;
          tet[0] = id(c.x, c.y, c.z);
          for (int s = 0; s < 2; ++s) {
            c[p[s]] += 1;
            tet[s + 1] = id(c.x, c.y, c.z);
          }
          tet[3] = id(i + 1, j + 1, k + 1);
          const glm::dvec3 a = mesh.vertices[tet[0]];
          if (glm::dot(glm::cross(mesh.vertices[tet[1]] - a, mesh.vertices[tet[2]] - a), mesh.vertices[tet[3]] - a) < 0)
            std::swap(tet[2], tet[3]);
          mesh.tets.push_back(tet);
          mesh.labels.push_back(label(glm::dvec3(i + 0.5, j + 0.5, k + 0.5)));
        }
  return mesh;
}

/// The id of the vertex at integer position (i, j, k) of kuhn_box(nx, ny, ...).
inline std::uint32_t box_vertex(int nx, int ny, int i, int j, int k) {
  return std::uint32_t(i + (nx + 1) * (j + (ny + 1) * k));
}

/// A fresh empty folder for one test, removed when the object dies.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("fracref_coarse_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::filesystem::path file(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = path_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// The message of the InputError that `f` throws ("" and a test failure when it throws none).
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

/// How many edges of S have the given kind.
inline int count_edges(const FractureSurface& s, std::uint8_t kind) {
  int n = 0;
  for (std::uint8_t k : s.edge_special) n += k == kind;
  return n;
}

}  // namespace fracref::test
