// Horn's closed-form absolute orientation (see rigid_fit.hpp).
#include "animate/rigid_fit.hpp"

#include <cmath>
#include <utility>

namespace fracref {
namespace {

// One Jacobi rotation zeroing a[p][q]; v collects the rotations (columns: eigenvectors).
void jacobi_rotate(double a[4][4], double v[4][4], int p, int q) {
  if (a[p][q] == 0.0) return;
  const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
  const double t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
  const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
  for (int k = 0; k < 4; ++k) {
    const double akp = a[k][p], akq = a[k][q];
    a[k][p] = c * akp - s * akq, a[k][q] = s * akp + c * akq;
  }
  for (int k = 0; k < 4; ++k) {
    const double apk = a[p][k], aqk = a[q][k];
    a[p][k] = c * apk - s * aqk, a[q][k] = s * apk + c * aqk;
  }
  for (int k = 0; k < 4; ++k) {
    const double vkp = v[k][p], vkq = v[k][q];
    v[k][p] = c * vkp - s * vkq, v[k][q] = s * vkp + c * vkq;
  }
}

}  // namespace

glm::dvec4 largest_eigenvector(const glm::dmat4& m) {
  double a[4][4], v[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) a[i][j] = m[j][i], v[i][j] = i == j ? 1.0 : 0.0;
  for (int sweep = 0; sweep < 64; ++sweep) {
    double off = 0.0, diag = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) (i == j ? diag : off) += a[i][j] * a[i][j];
    if (off <= 1e-30 * diag || off == 0.0) break;
    for (int p = 0; p < 3; ++p)
      for (int q = p + 1; q < 4; ++q) jacobi_rotate(a, v, p, q);
  }
  int best = 0;
  for (int i = 1; i < 4; ++i)
    if (a[i][i] > a[best][best]) best = i;
  const glm::dvec4 e(v[0][best], v[1][best], v[2][best], v[3][best]);
  return e / glm::length(e);
}

RigidPose fit_rigid(const glm::dvec3* rest, const glm::dvec3* moved, std::size_t count, const glm::dvec3& pivot,
                    const glm::dquat& near) {
  glm::dvec3 cr(0.0), cm(0.0);
  for (std::size_t i = 0; i < count; ++i) cr += rest[i], cm += moved[i];
  cr /= double(count), cm /= double(count);
  glm::dmat3 s(0.0);  // s[a][b] = sum of (rest - cr)_a (moved - cm)_b
  for (std::size_t i = 0; i < count; ++i) {
    const glm::dvec3 r = rest[i] - cr, x = moved[i] - cm;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) s[a][b] += r[a] * x[b];
  }
  const double n[4][4] = {
      {s[0][0] + s[1][1] + s[2][2], s[1][2] - s[2][1], s[2][0] - s[0][2], s[0][1] - s[1][0]},
      {s[1][2] - s[2][1], s[0][0] - s[1][1] - s[2][2], s[0][1] + s[1][0], s[2][0] + s[0][2]},
      {s[2][0] - s[0][2], s[0][1] + s[1][0], -s[0][0] + s[1][1] - s[2][2], s[1][2] + s[2][1]},
      {s[0][1] - s[1][0], s[2][0] + s[0][2], s[1][2] + s[2][1], -s[0][0] - s[1][1] + s[2][2]}};
  glm::dmat4 m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[j][i] = n[i][j];
  const glm::dvec4 e = largest_eigenvector(m);
  RigidPose pose;
  pose.rotation = glm::dquat(e[0], e[1], e[2], e[3]);
  const double along = glm::dot(pose.rotation, near);
  if (along < 0.0 || (along == 0.0 && pose.rotation.w < 0.0)) pose.rotation = -pose.rotation;
  // x = R (X - cr) + cm = R (X - pivot) + (R (pivot - cr) + cm).
  pose.translation = glm::mat3_cast(pose.rotation) * (pivot - cr) + cm;
  return pose;
}

}  // namespace fracref
