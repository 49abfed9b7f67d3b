// Metric algebra properties (chapter 7.6.1): lengths, eigen-decomposition, intersection,
// interpolation, anisotropy cap, varying-metric edge length.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "uvmesh/param/metric.h"

using namespace uvmesh::param;

namespace {

template <int N>
Metric<N> random_metric(std::mt19937& rng, double hmin = 0.01, double hmax = 10.0) {
  std::uniform_real_distribution<double> U(-1.0, 1.0), H(std::log(hmin), std::log(hmax));
  // Random rotation: Gram-Schmidt of random vectors.
  std::array<VecN<N>, N> d;
  for (int i = 0; i < N; ++i) {
    VecN<N> v;
    for (int k = 0; k < N; ++k) v[k] = U(rng);
    for (int j = 0; j < i; ++j) v -= glm::dot(v, d[j]) * d[j];
    d[i] = glm::normalize(v);
  }
  std::array<double, N> h;
  for (double& x : h) x = std::exp(H(rng));
  return Metric<N>::from_sizes(d, h);
}

template <int N>
VecN<N> random_vec(std::mt19937& rng) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  VecN<N> v;
  for (int k = 0; k < N; ++k) v[k] = U(rng);
  return v;
}

}  // namespace

TEST_CASE("metric: from_sizes gives unit length to h_i along d_i", "[param][metric]") {
  const Metric2 m = Metric2::from_sizes(
      {glm::dvec2(1, 1) / std::sqrt(2.0), glm::dvec2(-1, 1) / std::sqrt(2.0)}, {0.5, 4.0});
  CHECK(m.length(glm::dvec2(1, 1) / std::sqrt(2.0) * 0.5) == Approx(1.0));
  CHECK(m.length(glm::dvec2(-1, 1) / std::sqrt(2.0) * 4.0) == Approx(1.0));
  CHECK(m.anisotropy() == Approx(8.0));
  const auto h = m.sizes();
  CHECK(h[0] == Approx(0.5));
  CHECK(h[1] == Approx(4.0));
}

TEST_CASE("metric: eigen-decomposition reconstructs the matrix", "[param][metric]") {
  std::mt19937 rng(7);
  for (int t = 0; t < 500; ++t) {
    const Metric3 m = random_metric<3>(rng);
    const Eigen<3> e = m.eigen();
    CHECK(e.values[0] <= e.values[1]);
    CHECK(e.values[1] <= e.values[2]);
    const Metric3 r = Metric3::from_eigen(e.vectors, e.values);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) CHECK(r(i, j) == Approx(m(i, j)).margin(1e-9 * e.values[2]));
    CHECK(std::abs(glm::dot(e.vectors[0], e.vectors[1])) < 1e-12);
  }
}

TEMPLATE_TEST_CASE_SIG(
    "metric: intersection contains both unit balls' constraints and is the largest such",
    "[param][metric]", ((int N), N), 2, 3) {
  std::mt19937 rng(11 + N);
  for (int t = 0; t < 300; ++t) {
    const Metric<N> a = random_metric<N>(rng), b = random_metric<N>(rng);
    const Metric<N> c = intersect(a, b);
    REQUIRE(c.is_spd());
    // Its unit ball lies in both: |x|_C >= max(|x|_A, |x|_B) for every x.
    for (int k = 0; k < 50; ++k) {
      const VecN<N> x = random_vec<N>(rng);
      CHECK(c.length(x) >= std::max(a.length(x), b.length(x)) * (1.0 - 1e-9));
    }
    // Largest: along the common (simultaneously reducing) basis P = A^{-1/2} Q it is
    // exactly the max, so no metric smaller in any of those directions satisfies both.
    const Metric<N> aih = a.power(-0.5);
    Metric<N> cm;
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j)
        for (int k = 0; k < N; ++k)
          for (int l = 0; l < N; ++l) cm.m[i][j] += aih.m[i][k] * b.m[k][l] * aih.m[l][j];
    cm.symmetrize();
    const Eigen<N> e = cm.eigen();
    for (int i = 0; i < N; ++i) {
      const VecN<N> p = aih.apply(e.vectors[i]);
      CHECK(c.length(p) == Approx(std::max(a.length(p), b.length(p))).epsilon(1e-7));
    }
    // Intersecting with a coarser metric changes nothing; intersection is symmetric.
    const Metric<N> coarse = a * 0.25;  // sizes doubled
    const Metric<N> same = intersect(a, coarse);
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) {
        const double scale = a.eigen().values[N - 1];
        CHECK(same(i, j) == Approx(a(i, j)).margin(1e-9 * scale));
        CHECK(intersect(b, a)(i, j) ==
              Approx(c(i, j)).margin(1e-7 * (scale + b.eigen().values[N - 1])));
      }
  }
}

TEST_CASE("metric: interpolation is SPD and sizes vary linearly", "[param][metric]") {
  std::mt19937 rng(3);
  for (int t = 0; t < 200; ++t) {
    const Metric3 a = random_metric<3>(rng, 1e-3, 1e3), b = random_metric<3>(rng, 1e-3, 1e3),
                  c = random_metric<3>(rng, 1e-3, 1e3);
    for (double s : {0.0, 0.1, 0.5, 0.9, 1.0}) {
      const Metric3 m = interpolate(a, b, s);
      CHECK(m.is_spd());
    }
    CHECK(interpolate(a, b, c, {0.2, 0.3, 0.5}).is_spd());
    const Metric3 m0 = interpolate(a, b, 0.0);
    CHECK(m0(0, 1) == Approx(a(0, 1)).margin(1e-9 * a.eigen().values[2]));
  }
  // Isotropic sizes interpolate linearly: h(t) = (1-t) h0 + t h1.
  const Metric2 m = interpolate(Metric2::isotropic(1.0), Metric2::isotropic(3.0), 0.25);
  CHECK(m.sizes()[0] == Approx(1.5));
  CHECK(m.sizes()[1] == Approx(1.5));
}

TEST_CASE("metric: anisotropy cap keeps the finest size", "[param][metric]") {
  const Metric2 m = Metric2::from_sizes({glm::dvec2(1, 0), glm::dvec2(0, 1)}, {0.01, 100.0});
  const Metric2 c = m.capped(10.0);
  CHECK(c.anisotropy() == Approx(10.0));
  CHECK(c.sizes()[0] == Approx(0.01));
  CHECK(c.sizes()[1] == Approx(0.1));
  const Metric2 k = m.clamped(0.1, 10.0);
  CHECK(k.sizes()[0] == Approx(0.1));
  CHECK(k.sizes()[1] == Approx(10.0));
}

TEST_CASE("metric: edge length under a varying metric (eq. 7.10)", "[param][metric]") {
  // h(t) = h0 + (h1 - h0) t along e of Euclidean length d: l = d ln(h1/h0) / (h1 - h0).
  const double h0 = 0.1, h1 = 1.0, d = 2.0;
  auto M = [&](double t) { return Metric2::isotropic(h0 + (h1 - h0) * t); };
  const double l = edge_length<2>(M, glm::dvec2(d, 0.0), 1e-10);
  CHECK(l == Approx(d * std::log(h1 / h0) / (h1 - h0)).epsilon(1e-8));
  // Constant metric: the plain metric length.
  const Metric3 c = Metric3::from_sizes(
      {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)}, {1, 2, 4});
  CHECK(edge_length<3>([&](double) { return c; }, glm::dvec3(1, 2, 4)) == Approx(std::sqrt(3.0)));
}
