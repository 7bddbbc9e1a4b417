#include "flow/implicit_step.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "util/parallel.hpp"

namespace fracref {
namespace {

// Partial sums per chunk, added in chunk order: the chunks depend only on n, so the sum is the
// same double for any thread count.
template <class Fn>
double chunked_sum(std::size_t n, int threads, Fn fn) {
  const std::size_t chunks = chunk_count(n, 2048);
  std::vector<double> part(chunks, 0.0);
  parallel_chunks(n, chunks, threads, [&](std::size_t c, std::size_t b, std::size_t e) { part[c] = fn(b, e); });
  double sum = 0.0;
  for (double p : part) sum += p;
  return sum;
}

template <class Fn>
void chunked_for(std::size_t n, int threads, Fn fn) {
  parallel_chunks(n, chunk_count(n, 2048), threads, [&](std::size_t, std::size_t b, std::size_t e) { fn(b, e); });
}

double dot3(const glm::dvec3& a, const glm::dvec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// M + dt L_ψ in rows: the diagonal, and per row its neighbours with −dt w (only the first
// row_len[i] of the row's 2·degree slots are used).
struct Matrix {
  std::vector<double> diag;
  std::vector<std::uint32_t> offsets, row_len, cols;
  std::vector<double> values;
  std::vector<char> fixed;
};

// Per face, ½ ψ̄ cot of the angle at each corner: the weight that face gives the opposite edge.
std::vector<glm::dvec3> face_half_weights(const SurfaceView& s, std::span<const glm::vec4> samples, int threads) {
  std::vector<glm::dvec3> half(s.faces.size());
  chunked_for(half.size(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) {
      const glm::uvec4 f = s.faces[j];
      const glm::dvec3 x[3] = {glm::dvec3(glm::vec3(s.positions[f.x])), glm::dvec3(glm::vec3(s.positions[f.y])),
                               glm::dvec3(glm::vec3(s.positions[f.z]))};
      const double psi = (double(samples[f.x].x) + samples[f.y].x + samples[f.z].x) / 3.0;
      for (int k = 0; k < 3; ++k) half[j][k] = 0.5 * psi * corner_cotangents(x[(k + 2) % 3], x[k], x[(k + 1) % 3]).x;
    }
  });
  return half;
}

// Row i gathers, per neighbour, the weights of the faces on their edge in face order (vf_faces is
// ascending), so rows i and k add the same terms in the same order: the matrix is exactly
// symmetric.
Matrix assemble(const SurfaceView& s, std::span<const glm::vec4> samples, std::span<const glm::vec4> velocity,
                double dt, int threads) {
  const std::size_t n = s.positions.size();
  const std::vector<glm::dvec3> half = face_half_weights(s, samples, threads);
  Matrix m;
  m.diag.assign(n, 0.0), m.row_len.assign(n, 0), m.fixed.assign(n, 0);
  m.offsets.resize(n + 1);
  for (std::size_t i = 0; i <= n; ++i) m.offsets[i] = 2 * s.vf_offsets[i];
  m.cols.resize(m.offsets[n]), m.values.resize(m.offsets[n]);
  chunked_for(n, threads, [&](std::size_t b, std::size_t e) {
    std::vector<std::pair<std::uint32_t, double>> row;
    for (std::size_t i = b; i < e; ++i) {
      row.clear();
      for (std::uint32_t k = s.vf_offsets[i]; k < s.vf_offsets[i + 1]; ++k) {
        const std::uint32_t j = s.vf_faces[k];
        const glm::uvec4 f = s.faces[j];
        const int c = f.x == i ? 0 : f.y == i ? 1 : 2;
        row.emplace_back(f[(c + 1) % 3], half[j][(c + 2) % 3]);
        row.emplace_back(f[(c + 2) % 3], half[j][(c + 1) % 3]);
      }
      std::stable_sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      const double mass = double(velocity[i].w);
      double diag = mass;
      std::uint32_t out = m.offsets[i];
      for (std::size_t r = 0; r < row.size();) {
        double w = 0.0;
        const std::uint32_t col = row[r].first;
        for (; r < row.size() && row[r].first == col; ++r) w += row[r].second;
        if (w == 0.0) continue;
        diag += dt * w;
        m.cols[out] = col, m.values[out] = -dt * w;
        ++out;
      }
      m.row_len[i] = out - m.offsets[i];
      m.diag[i] = diag;
      m.fixed[i] = !(mass > 0.0);
    }
  });
  return m;
}

class ConjugateGradients {
 public:
  ConjugateGradients(const Matrix& m, std::span<const glm::dmat3> filter, int threads)
      : m_(m), filter_(filter), threads_(threads) {}
  ImplicitStepStats solve(std::vector<glm::dvec3> rhs, std::span<glm::dvec3> x, const ImplicitStepOptions& o);

 private:
  double multiply(const std::vector<glm::dvec3>& p, std::vector<glm::dvec3>& q) const;
  glm::dvec3 filtered(std::size_t i, const glm::dvec3& v) const { return filter_.empty() ? v : filter_[i] * v; }
  const Matrix& m_;
  std::span<const glm::dmat3> filter_;
  int threads_;
};

// q = A p (fixed rows and columns out), returns p·q.
double ConjugateGradients::multiply(const std::vector<glm::dvec3>& p, std::vector<glm::dvec3>& q) const {
  return chunked_sum(p.size(), threads_, [&](std::size_t b, std::size_t e) {
    double sum = 0.0;
    for (std::size_t i = b; i < e; ++i) {
      if (m_.fixed[i]) {
        q[i] = glm::dvec3(0.0);
        continue;
      }
      glm::dvec3 acc = m_.diag[i] * p[i];
      for (std::uint32_t k = m_.offsets[i], end = k + m_.row_len[i]; k < end; ++k)
        if (!m_.fixed[m_.cols[k]]) acc += m_.values[k] * p[m_.cols[k]];
      q[i] = filtered(i, acc);
      sum += dot3(p[i], q[i]);
    }
    return sum;
  });
}

ImplicitStepStats ConjugateGradients::solve(std::vector<glm::dvec3> r, std::span<glm::dvec3> x,
                                            const ImplicitStepOptions& o) {
  const std::size_t n = r.size();
  std::vector<glm::dvec3> z(n), p(n), q(n);
  // The goal is relative to the residual at x = 0 (b's), whatever the guess.
  const double rb = chunked_sum(n, threads_, [&](std::size_t b, std::size_t e) {
    double sum = 0.0;
    for (std::size_t i = b; i < e; ++i)
      if (!m_.fixed[i]) sum += dot3(filtered(i, r[i]), filtered(i, r[i])) / m_.diag[i];
    return sum;
  });
  // Start from the guess in x (its allowed part): r = b − A x.
  for (std::size_t i = 0; i < n; ++i) p[i] = m_.fixed[i] ? glm::dvec3(0.0) : filtered(i, x[i]);
  multiply(p, q);
  for (std::size_t i = 0; i < n; ++i) x[i] = p[i], r[i] -= q[i];
  auto precondition = [&](std::size_t b, std::size_t e) {
    double sum = 0.0;
    for (std::size_t i = b; i < e; ++i) {
      r[i] = m_.fixed[i] ? glm::dvec3(0.0) : filtered(i, r[i]);
      z[i] = m_.fixed[i] ? glm::dvec3(0.0) : r[i] / m_.diag[i];
      sum += dot3(r[i], z[i]);
    }
    return sum;
  };
  double rz = chunked_sum(n, threads_, precondition);
  p = z;
  ImplicitStepStats st;
  const double goal = o.tolerance * o.tolerance * rb;
  while (rz > goal && rz > 0.0 && st.iterations < o.max_iterations) {
    const double pq = multiply(p, q);
    if (!(pq > 0.0)) break;
    const double alpha = rz / pq;
    const double rz_next = chunked_sum(n, threads_, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) x[i] += alpha * p[i], r[i] -= alpha * q[i];
      return precondition(b, e);
    });
    const double beta = rz_next / rz;
    rz = rz_next;
    chunked_for(n, threads_, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) p[i] = z[i] + beta * p[i];
    });
    ++st.iterations;
  }
  st.relative_residual = rb > 0.0 ? std::sqrt(rz / rb) : 0.0;
  return st;
}

}  // namespace

glm::dvec2 corner_cotangents(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  auto cot = [](const glm::dvec3& u, const glm::dvec3& v) {
    const double s = glm::length(glm::cross(u, v));
    return s > 0.0 ? dot3(u, v) / s : 0.0;
  };
  return {cot(p - a, b - a), cot(a - b, p - b)};
}

ImplicitStepStats implicit_step(const SurfaceView& s, std::span<const glm::vec4> samples,
                                std::span<const glm::vec4> velocity, double dt, std::span<const glm::dmat3> filter,
                                std::span<glm::dvec3> displacement, const ImplicitStepOptions& o) {
  const std::size_t n = s.positions.size();
  const Matrix m = assemble(s, samples, velocity, dt, o.threads);
  std::vector<glm::dvec3> rhs(n);
  for (std::size_t i = 0; i < n; ++i) rhs[i] = dt * double(velocity[i].w) * glm::dvec3(glm::vec3(velocity[i]));
  return ConjugateGradients(m, filter, o.threads).solve(std::move(rhs), displacement, o);
}

}  // namespace fracref
