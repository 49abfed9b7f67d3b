// Exact geometric predicates on doubles: adaptive-precision orient2d and incircle
// (floating-point filter, then exact expansion arithmetic). The sign is always exact,
// whatever the input doubles, so collinear, cocircular, duplicate and nearly coincident
// points never give an inconsistent answer (reference chapter §7.1.4, practical issues).
//
// Guarantees (details and proofs in src/predicates.cpp): the sign is exact for every
// finite input, from subnormals to 1e308 and any mix of magnitudes; non-finite inputs
// give an unspecified result. The returned magnitude is approximate (no worse than plain
// double evaluation). No global state: safe to call from any number of threads. Cost:
// a few dozen flops when the floating-point filter decides (almost always); only
// nearly degenerate inputs pay for the exact stages.
//
// Usage:
//   double o = uvmesh::m2d::pred::orient2d(a, b, c);   // > 0: a, b, c counter-clockwise
//   double i = uvmesh::m2d::pred::incircle(a, b, c, d); // > 0: d inside circle(a, b, c), abc CCW
#pragma once

namespace uvmesh::m2d::pred {

// Twice the signed area of triangle abc; positive when counter-clockwise. Exact sign.
double orient2d(const double* a, const double* b, const double* c);

// Positive when d lies inside the circle through a, b, c (a, b, c counter-clockwise),
// negative outside, zero when cocircular. Exact sign.
double incircle(const double* a, const double* b, const double* c, const double* d);

// Non-adaptive, plain floating-point versions (for tests and benchmarks only).
double orient2d_fast(const double* a, const double* b, const double* c);
double incircle_fast(const double* a, const double* b, const double* c, const double* d);

}  // namespace uvmesh::m2d::pred
