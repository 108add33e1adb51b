// The subdivision's Bernstein coefficients against exact references (plugin/core/
// roots_bernstein_nodes.h, a private header): the conversion from 0 of solveTop's start at 0
// (bernsteinFromZero) with its rounding bounds, on both sides of 0, for the plain nodes
// (one uniform bound, degrees up to 12) and the paired ones (a bound per coefficient).
// Reference: b_i = sum_{j <= i} C(i, j) / C(n, j) c_j h^j on the node from 0 to h > 0
// (Farin, "Curves and Surfaces for CAGD", Sec. 5.4: the monomial-to-Bernstein matrix), in
// MPFR at 256 bits; on the node from h < 0 to 0 the same for G(-|h| u) read backwards.
#include "roots_subdivide.h"

#include <gtest/gtest.h>

#include <random>

#include "roots_mpfr.h"

namespace algray {
namespace {

using roots_detail::BPair;
using roots_detail::Deg;
using roots_detail::LocalPoly;
using test::Mp;

// Exact Bernstein coefficients of sum c_j v^j on the node between lo and hi (lo < hi),
// b_0 at lo, by the blossom: b_i is the polar form at (lo x (n - i), hi x i), the
// average over the C(n, j) choices of j of the n arguments of their products, times c_j.
// For the monomial v^j that is sum_k C(i, k) C(n - i, j - k) hi^k lo^(j - k) / C(n, j).
std::vector<double> exactBernstein(const std::vector<double>& c, double lo, double hi) {
  const int n = static_cast<int>(c.size()) - 1;
  auto binom = [](int a, int b) {
    double r = 1;
    for (int t = 1; t <= b; ++t) r = r * (a - b + t) / t;
    return r;  // exact for the sizes here (n <= 40)
  };
  std::vector<double> out(c.size());
  for (int i = 0; i <= n; ++i) {
    Mp sum;
    for (int j = 0; j <= n; ++j) {
      Mp polar;
      for (int k = std::max(0, j - (n - i)); k <= std::min(i, j); ++k) {
        Mp term(binom(i, k) * binom(n - i, j - k));
        for (int t = 0; t < k; ++t) mpfr_mul_d(term.get(), term.get(), hi, MPFR_RNDN);
        for (int t = 0; t < j - k; ++t) mpfr_mul_d(term.get(), term.get(), lo, MPFR_RNDN);
        mpfr_add(polar.get(), polar.get(), term.get(), MPFR_RNDN);
      }
      mpfr_div_d(polar.get(), polar.get(), binom(n, j), MPFR_RNDN);
      mpfr_mul_d(polar.get(), polar.get(), c[j], MPFR_RNDN);
      mpfr_add(sum.get(), sum.get(), polar.get(), MPFR_RNDN);
    }
    out[i] = mpfr_get_d(sum.get(), MPFR_RNDN);
  }
  return out;
}

template <int N>
void checkDegree(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uni(-1, 1);
  using E = typename roots_detail::NodeElement<double, Deg<N>>::type;
  constexpr bool kPairs = !std::is_same_v<E, double>;
  for (int trial = 0; trial < 200; ++trial) {
    LocalPoly<double> g;
    g.n = N;
    std::vector<double> c(N + 1);
    for (int j = 0; j <= N; ++j)
      c[j] = g.c[j] = uni(rng) * std::pow(10.0, 3 * uni(rng));  // cancelling terms
    for (const double h : {-(0.25 + 0.75 * std::abs(uni(rng))), 0.25 + 0.75 * std::abs(uni(rng))}) {
      E b[kMaxDegree + 1];
      const double err = roots_detail::bernsteinFromZero(g, Deg<N>{}, h, b);
      const std::vector<double> ref = h < 0 ? exactBernstein(c, h, 0.0) : exactBernstein(c, 0.0, h);
      for (int i = 0; i <= N; ++i) {
        const double got = roots_detail::coeff<double>(b[i]);
        const double bound = kPairs ? roots_detail::bound<double>(b[i]) : err;
        // The reference is rounded once (half an ulp of it): the bound must cover the rest.
        EXPECT_LE(std::abs(got - ref[i]), bound + 0x1p-53 * std::abs(ref[i]))
            << "degree " << N << " h " << h << " i " << i << " got " << got << " exact " << ref[i];
      }
      // The ends are G at the node's ends: b_0 at the left end, b_n at the right end.
      const double atH = [&] {
        double v = 0;
        for (int j = N; j >= 0; --j) v = v * h + c[j];
        return v;
      }();
      EXPECT_NEAR(roots_detail::coeff<double>(b[h < 0 ? 0 : N]), atH,
                  1e-12 * (std::abs(atH) + 1e3 * (N + 1)));
      EXPECT_EQ(roots_detail::coeff<double>(b[h < 0 ? N : 0]), c[0]);
    }
  }
}

TEST(RootsSubdivide, BernsteinFromZeroWithinItsBounds) {
  std::mt19937_64 rng(1203);
  checkDegree<3>(rng);
  checkDegree<6>(rng);
  checkDegree<8>(rng);
  checkDegree<11>(rng);
  checkDegree<12>(rng);  // the last plain degree (kPairNodeDegree)
  checkDegree<13>(rng);  // pairs from here on
  checkDegree<16>(rng);
  checkDegree<20>(rng);
}

// The noise-node rule's proof (provedWithinNoise, degrees above 20): where it says |G| <=
// 4 N(|v|) on a node (N the noise bound), G evaluated in long double at 1001 points of the
// node must agree; random nodes (on either side of 0, around it, next to it) and random G
// against random noise coefficients, at scales where the proof holds and where it fails
// (both must occur). Then the factor itself, on nodes left and right of 0 across which N
// grows 6.5-fold: G = 2N (odd terms negated on the left, G(v) = 2 N(|v|)) is proved, G = 5N
// is not.
TEST(RootsSubdivide, NoiseNodeProofHoldsWhereItClaims) {
  constexpr int n = 25;  // a run-time degree, paired nodes
  using E = BPair<double>;
  std::mt19937_64 rng(2012);
  std::uniform_real_distribution<double> uni(0, 1);
  auto prove = [](const LocalPoly<double>& g, double va, double vb) {
    LocalPoly<double> node = g;
    node.lo = va;
    node.hi = vb;
    E b[kMaxDegree + 1];
    roots_detail::toBernsteinWithBound(node, n, b);
    const double delta = 0x1p-52 * (std::abs(va) + (vb - va));
    return roots_detail::provedWithinNoise(node, n, b, va, vb, delta);
  };
  int proved = 0, refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    LocalPoly<double> g;
    g.n = n;
    const double scale = std::ldexp(1.0, static_cast<int>(rng() % 9) - 2);
    for (int j = 0; j <= n; ++j) {
      g.noise[j] = rng() % 4 == 0 ? 0.0 : std::ldexp(uni(rng), -40);
      g.c[j] = g.noise[j] * scale * (2 * uni(rng) - 1);
    }
    g.noise[0] = std::ldexp(0.5 + uni(rng), -40);
    double va = 2 * uni(rng) - 1, vb = 2 * uni(rng) - 1;
    if (va > vb) std::swap(va, vb);
    if (trial % 3 == 0) vb = va + (vb - va) * 1e-3;  // short nodes: N nearly constant
    if (!(va < vb)) continue;
    if (!prove(g, va, vb)) {
      ++refused;
      continue;
    }
    ++proved;
    for (int k = 0; k <= 1000; ++k) {
      const long double v = va + (static_cast<long double>(vb) - va) * k / 1000;
      long double f = 0, nb = 0;
      for (int j = n; j >= 0; --j) {
        f = f * v + g.c[j];
        nb = nb * std::fabs(v) + g.noise[j];
      }
      ASSERT_LE(std::fabs(f), 4 * nb * (1 + 1e-12L)) << "trial " << trial << " node [" << va << ", "
                                                     << vb << "] at " << static_cast<double>(v);
    }
  }
  EXPECT_GT(proved, 300);
  EXPECT_GT(refused, 300);
  for (const double factor : {2.0, 5.0}) {
    LocalPoly<double> g;
    g.n = n;
    for (int j = 0; j <= n; ++j) g.noise[j] = 0x1p-45;
    for (const auto& [va, vb] : {std::pair{0.3, 0.9}, std::pair{-0.9, -0.3}}) {
      for (int j = 0; j <= n; ++j) g.c[j] = factor * g.noise[j] * (va < 0 && j % 2 ? -1 : 1);
      EXPECT_EQ(prove(g, va, vb), factor < 4)
          << "G = " << factor << " N on [" << va << ", " << vb << "]";
    }
  }
}

}  // namespace
}  // namespace algray
