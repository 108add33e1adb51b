// The math core's AVX2 kernels (plugin/core/core_isa.h: HornerForm::evaluate's z-rows,
// the direct restriction over a HornerForm's box) against its baseline SSE2 ones, bit for
// bit, in one process: random polynomials of degree 1-20 (dense and sparse, coefficients
// from subnormal to huge), random points and rays with zeros of either sign, subnormal,
// huge and non-finite components. (The other suites run on the machine's default kernels;
// ctest runs taylor_test and horner_form_test once more with ALGRAY_CORE_ISA=sse2.)
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "algray/gallery.h"
#include "algray/horner_form.h"
#include "algray/taylor.h"
#include "core_isa.h"
#include "support/scales.h"

namespace algray {
namespace {

using core_isa::Isa;

bool sameBits(double a, double b) {
  return std::isnan(a) ? std::isnan(b)
                       : std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

// A value of random sign and magnitude: mostly near 1, sometimes 0, -0, subnormal, tiny or
// huge.
double wild(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double v = u(rng);
  switch (std::uniform_int_distribution<int>(0, 15)(rng)) {
    case 0:
      return 0.0;
    case 1:
      return -0.0;
    case 2:
      return v * 0x1p-1060;  // subnormal
    case 3:
      return v * 1e-300;
    case 4:
      return v * 1e150;
    case 5:
      return v * 1e-150;
    default:
      return v * 4.0;
  }
}

std::vector<Polynomial> polynomials(std::mt19937_64& rng) {
  std::vector<Polynomial> polys = {Polynomial(), Polynomial(-0.0), Polynomial::variable(2)};
  for (const GallerySurface& s : gallery()) polys.push_back(s.build());
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int m = 1; m <= 20; ++m)
    for (double density : {0.15, 0.6, 1.0}) {
      Polynomial f;
      for (int n = 0; n <= m; ++n)
        forEachMonomialOfDegree(n, [&](int i, int j, int k, int) {
          if (u(rng) < density) f.setCoeff(i, j, k, wild(rng));
        });
      f.setCoeff(0, 0, m, 1.0);  // keep the degree
      polys.push_back(f);
    }
  // Even in every subset of the axes (HornerForm::evaluate runs F(x^2, y, z) etc.).
  for (unsigned mask = 1; mask < 8; ++mask)
    for (int m : {4, 10, 16}) {
      Polynomial f;
      test::forEachMonomialEvenOn(mask, m, [&](int i, int j, int k) {
        if (u(rng) < 0.6) f.setCoeff(i, j, k, wild(rng));
      });
      for (int a = 0; a < 3; ++a) {
        int e[3] = {0, 0, 0};
        e[a] = (mask >> a & 1u) ? m : 1;
        f.setCoeff(e[0], e[1], e[2], 1.0);  // every axis decided, the degree kept
      }
      EXPECT_EQ(HornerForm(f).evenAxes(), mask);
      polys.push_back(f);
    }
  return polys;
}

std::vector<glm::dvec3> points(std::mt19937_64& rng) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<glm::dvec3> out = {glm::dvec3(0.0), glm::dvec3(-0.0, 0.0, -0.0),
                                 glm::dvec3(1.0, -0.0, 0.5), glm::dvec3(kInf, 0.5, -0.25),
                                 glm::dvec3(0.5, std::nan(""), 1.0)};
  for (int i = 0; i < 40; ++i) out.push_back({wild(rng), wild(rng), wild(rng)});
  return out;
}

// The other suites test the kernels the process picks: AVX2 wherever the CPU has it.
TEST(CoreIsaDefault, Avx2WhereTheCpuHasIt) {
  if (std::getenv("ALGRAY_CORE_ISA") != nullptr) GTEST_SKIP() << "ALGRAY_CORE_ISA is set";
#if ALGRAY_CORE_AVX2
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) {
    EXPECT_EQ(core_isa::active(), Isa::kAvx2);
  }
#endif
}

class CoreIsa : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!core_isa::select(Isa::kAvx2)) GTEST_SKIP() << "no AVX2 on this CPU or build";
  }
  void TearDown() override { core_isa::select(before_); }
  Isa before_ = core_isa::active();
};

TEST_F(CoreIsa, EvaluateIsTheBaselineBitForBit) {
  std::mt19937_64 rng(77);
  const std::vector<glm::dvec3> ps = points(rng);
  for (const Polynomial& f : polynomials(rng)) {
    const HornerForm h(f);
    for (const glm::dvec3& p : ps) {
      ASSERT_TRUE(core_isa::select(Isa::kSse2));
      const auto want = h.evaluate(p);
      ASSERT_TRUE(core_isa::select(Isa::kAvx2));
      const auto got = h.evaluate(p);
      const std::string what = "degree " + std::to_string(f.degree());
      EXPECT_TRUE(sameBits(got.value, want.value)) << what;
      EXPECT_TRUE(sameBits(got.magnitude, want.magnitude)) << what;
      EXPECT_TRUE(sameBits(got.valueError, want.valueError)) << what;
      for (int a = 0; a < 3; ++a) EXPECT_TRUE(sameBits(got.gradient[a], want.gradient[a])) << what;
    }
  }
}

TEST_F(CoreIsa, RestrictionIsTheBaselineBitForBit) {
  std::mt19937_64 rng(78);
  const std::vector<glm::dvec3> ps = points(rng);
  std::vector<glm::dvec3> ds = {glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(-0.0, 1.0, -0.0),
                                glm::dvec3(0.0, -0.6, 0.8)};
  for (int i = 0; i < 12; ++i) ds.push_back({wild(rng), wild(rng), wild(rng)});
  int onSquares = 0;  // rays of even polynomials on squared coordinates (taylor_box.cpp)
  for (const Polynomial& f : polynomials(rng)) {
    const HornerForm h(f);
    for (std::size_t i = 0; i < ps.size(); ++i)
      for (std::size_t k = 0; k < ds.size(); k += 1 + i % 3) {
        const glm::dvec3& o = ps[i];
        const glm::dvec3& d = ds[k];
        const double tShift = k % 2 == 0 ? 0.0 : closestParameter(o, d, glm::dvec3(0.0));
        onSquares += h.restrictsOnSquares(tShift == 0.0 ? o : o + tShift * d, d) ? 1 : 0;
        ASSERT_TRUE(core_isa::select(Isa::kSse2));
        const RayPolynomial want = restrictToRay(h, o, d, tShift);
        ASSERT_TRUE(core_isa::select(Isa::kAvx2));
        const RayPolynomial got = restrictToRay(h, o, d, tShift);
        const std::string what = "degree " + std::to_string(f.degree()) + " point " +
                                 std::to_string(i) + " direction " + std::to_string(k);
        ASSERT_EQ(got.degree, want.degree) << what;
        for (int n = 0; n <= want.degree; ++n) {
          EXPECT_TRUE(sameBits(got.coeff[n], want.coeff[n])) << what << " coefficient " << n;
          EXPECT_TRUE(sameBits(got.error[n], want.error[n])) << what << " bound " << n;
        }
      }
  }
  EXPECT_GT(onSquares, 1000);
}

}  // namespace
}  // namespace algray
