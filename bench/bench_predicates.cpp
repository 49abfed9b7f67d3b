// Micro-benchmark for the exact predicates, printed beside the plain (inexact) double
// evaluation measured in the same run as a reference. Standalone, not wired into CMake:
//   g++ -O2 -std=c++20 -I mesher2d/include bench/bench_predicates.cpp mesher2d/src/predicates.cpp
//   ./a.out [seconds-per-measurement]
// Input sets:
//   random      points uniform in [0,1]^2 (the filter decides almost everything)
//   near-degen  orient2d: c = a + t (b - a) rounded (filter fails, exact stages run);
//               incircle: four points rounded onto one circle
//   exact-degen integer grid, exactly collinear / cocircular (filter fails, stage B
//               proves zero from exact differences)
//   inexact-deg exactly collinear points whose differences are inexact (stage D)
#include <uvmesh/mesher2d/predicates.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

namespace {

namespace pred = uvmesh::m2d::pred;

struct Pt {
  double x[2];
};

// Triples (orient2d) or quadruples (incircle) stored contiguously.
using Set = std::vector<Pt>;

template <class F>
double rate(const Set& pts, int arity, F f, double seconds, double& sink) {
  const std::size_t n = pts.size() / static_cast<std::size_t>(arity);
  using clock = std::chrono::steady_clock;
  std::size_t calls = 0;
  double acc = 0.0;
  const auto t0 = clock::now();
  double elapsed = 0.0;
  do {
    for (std::size_t i = 0; i < n; ++i) acc += f(&pts[i * static_cast<std::size_t>(arity)]);
    calls += n;
    elapsed = std::chrono::duration<double>(clock::now() - t0).count();
  } while (elapsed < seconds);
  sink += acc;
  return static_cast<double>(calls) / elapsed * 1e-6;
}

double orient(const Pt* p) {
  const double v = pred::orient2d(p[0].x, p[1].x, p[2].x);
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}
double orient_fast(const Pt* p) {
  const double v = pred::orient2d_fast(p[0].x, p[1].x, p[2].x);
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}
double incircle(const Pt* p) {
  const double v = pred::incircle(p[0].x, p[1].x, p[2].x, p[3].x);
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}
double incircle_fast(const Pt* p) {
  const double v = pred::incircle_fast(p[0].x, p[1].x, p[2].x, p[3].x);
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 0.5;
  const std::size_t n = 1 << 14;  // configurations per set (fits in L2)
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_real_distribution<double> ang(0.0, 6.283185307179586);
  std::uniform_int_distribution<int> gi(-100, 100);

  Set o_rand, o_near, o_grid, o_inexact, i_rand, i_near, i_grid;
  for (std::size_t k = 0; k < n; ++k) {
    for (int j = 0; j < 3; ++j) o_rand.push_back({{u(rng), u(rng)}});
    for (int j = 0; j < 4; ++j) i_rand.push_back({{u(rng), u(rng)}});

    const Pt a{{u(rng), u(rng)}}, b{{u(rng), u(rng)}};
    const double t = u(rng);
    o_near.push_back(a);
    o_near.push_back(b);
    o_near.push_back({{a.x[0] + t * (b.x[0] - a.x[0]), a.x[1] + t * (b.x[1] - a.x[1])}});

    const double cx = u(rng), cy = u(rng), r = 0.01 + u(rng);
    for (int j = 0; j < 4; ++j) {
      const double th = ang(rng);
      i_near.push_back({{cx + r * std::cos(th), cy + r * std::sin(th)}});
    }

    const int gx = gi(rng), gy = gi(rng), dx = gi(rng) % 7, dy = gi(rng) % 7;
    for (int j = 0; j < 3; ++j) o_grid.push_back({{double(gx + j * dx), double(gy + j * dy)}});
    // Lattice points on x^2 + y^2 = 25 around an integer center.
    static const int c5[12][2] = {{5, 0},  {4, 3},   {3, 4},   {0, 5},  {-3, 4}, {-4, 3},
                                  {-5, 0}, {-4, -3}, {-3, -4}, {0, -5}, {3, -4}, {4, -3}};
    const int s = static_cast<int>(k % 12);
    for (int j = 0; j < 4; ++j) {
      const int* q = c5[(s + 3 * j) % 12];
      i_grid.push_back({{double(gx + q[0]), double(gy + q[1])}});
    }

    // Exactly on 3y = 5x, at distances 2^-20 .. 2^20 from the origin.
    for (int j = 0; j < 3; ++j) {
      const double m =
          std::ldexp(std::floor(u(rng) * 0x1p50), -50 + static_cast<int>(k % 41) - 20 + 7 * j);
      o_inexact.push_back({{3.0 * m, 5.0 * m}});
    }
  }

  double sink = 0.0;
  std::printf("Mpredicates/s (%zu configurations per set, %.2f s per measurement)\n", n, seconds);
  std::printf("%-28s %12s %12s\n", "input", "exact", "plain double");
  std::printf("%-28s %12.1f %12.1f\n", "orient2d random", rate(o_rand, 3, orient, seconds, sink),
              rate(o_rand, 3, orient_fast, seconds, sink));
  std::printf("%-28s %12.1f %12.1f\n", "orient2d nearly collinear",
              rate(o_near, 3, orient, seconds, sink), rate(o_near, 3, orient_fast, seconds, sink));
  std::printf("%-28s %12.1f %12.1f\n", "orient2d collinear grid",
              rate(o_grid, 3, orient, seconds, sink), rate(o_grid, 3, orient_fast, seconds, sink));
  std::printf("%-28s %12.1f %12.1f\n", "orient2d collinear inexact",
              rate(o_inexact, 3, orient, seconds, sink),
              rate(o_inexact, 3, orient_fast, seconds, sink));
  std::printf("%-28s %12.1f %12.1f\n", "incircle random", rate(i_rand, 4, incircle, seconds, sink),
              rate(i_rand, 4, incircle_fast, seconds, sink));
  std::printf("%-28s %12.1f %12.1f\n", "incircle nearly cocircular",
              rate(i_near, 4, incircle, seconds, sink),
              rate(i_near, 4, incircle_fast, seconds, sink));
  std::printf("%-28s %12.1f %12.1f\n", "incircle cocircular grid",
              rate(i_grid, 4, incircle, seconds, sink),
              rate(i_grid, 4, incircle_fast, seconds, sink));
  std::printf("(checksum %g)\n", sink);
  return 0;
}
