#include "algray/horner_form.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>

#include "core_isa.h"
#include "isa_target.h"
#include "ray_horner.h"

namespace algray {

namespace {

// Error bound of the nested Horner scheme (Higham, Sec. 5.1 applied per level).
//
// One level, q_K = c_K, q_k = fl(fl(t q_{k+1}) + c_k): c_k enters with one rounding (the
// addition) and then goes through k multiply-add steps, so the computed q_0 is
// sum_k c_k (1 + theta_{2k+1}) t^k (Higham, Lemma 3.1 and Eq. (5.3)). The code starts
// from q = 0 (0 * t + c_K is exact for finite t), which changes nothing.
// Nested: a z-row value Q_ij is the coefficient of the y-level, the block value P_i the
// coefficient of the x-level, so c_ijk collects at most (2k+1) + (2j+1) + (2i+1) <= 2m+3
// roundings and
//   |computed f - f| <= gamma_{2m+3} E,   E = sum |c_ijk| |x|^i |y|^j |z|^k.
// E is computed by the same scheme over |c|, |x|, |y|, |z|: all terms non-negative, so
// the computed Ê >= (1 - gamma_{2m+3}) E and the bound is gamma/(1 - gamma) * Ê. The
// factor kSlack = 1 + 2^-40 covers the few roundings of that constant and of the final
// product (each <= u = 2^-53) and the underflow term of Ê below (<= (2m+3) 2^-75).
//
// Underflow (Higham, Eq. (2.8)): a product may also err by an absolute eta <= 2^-1075
// (sums of doubles are exact when subnormal). Each such eta is added at a coefficient
// slot (i, j, k) of the box (at most 3 per slot: one per level) and then travels the path
// of that slot's coefficient, so it is covered by adding kUnderflowFloor to |c| in every
// stored slot. With flush-to-zero (Embree's and TBB's worker threads) every product and
// sum below 2^-1022 becomes 0, an eta < 2^-1022, two per level, and a subnormal
// coefficient reads as 0 (DAZ): 7 * 2^-1022 (1 + gamma) per slot, which gamma_3
// kUnderflowFloor covers from 2^-968 on. 2^-966 changes E only for polynomials whose every
// value is below ~1e-285. (2^-1000 covered gradual underflow only: random polynomials
// with coefficients near 1e250 at points near 1e-120 broke their bound under FTZ.)
constexpr double kUnderflowFloor = 0x1p-966;
constexpr double kSlack = 1.0 + 0x1p-40;

// The z-rows of evaluate(), four at a time (see there): each row's value q, z-derivative
// qz and magnitude qa into rq, rqz, rqa. GroupSlot is HornerForm's (a template: the type is
// private).
template <class GroupSlot>
inline void zRows(const GroupSlot* s, const std::uint16_t* lane,
                  std::span<const std::uint8_t> groupLength, double z, double* rq, double* rqz,
                  double* rqa) {
  typedef double V2 __attribute__((vector_size(16)));
  const double az = std::abs(z);
  const V2 zz = {z, z}, azz = {az, az};
  for (const std::uint8_t len : groupLength) {
    V2 q0 = {0.0, 0.0}, qz0 = {0.0, 0.0}, qa0 = {0.0, 0.0};
    V2 q1 = {0.0, 0.0}, qz1 = {0.0, 0.0}, qa1 = {0.0, 0.0};
    for (const GroupSlot* end = s + len; s != end; ++s) {
      V2 c0, c1, a0, a1;
      std::memcpy(&c0, s->c, sizeof c0);
      std::memcpy(&c1, s->c + 2, sizeof c1);
      std::memcpy(&a0, s->absC, sizeof a0);
      std::memcpy(&a1, s->absC + 2, sizeof a1);
      qz0 = qz0 * zz + q0;
      qz1 = qz1 * zz + q1;
      q0 = q0 * zz + c0;
      q1 = q1 * zz + c1;
      qa0 = qa0 * azz + a0;
      qa1 = qa1 * azz + a1;
    }
    // The spare lanes of a short last group repeat its last row: stored in lane order,
    // the real row's own value lands last either way (the same value).
    const V2 q[2] = {q0, q1}, qz[2] = {qz0, qz1}, qa[2] = {qa0, qa1};
    for (int l = 0; l < 4; ++l) {
      rq[lane[l]] = q[l / 2][l % 2];
      rqz[lane[l]] = qz[l / 2][l % 2];
      rqa[lane[l]] = qa[l / 2][l % 2];
    }
    lane += 4;
  }
}

#if ALGRAY_CORE_AVX2
// The same with four rows in one 4-double AVX vector (core_isa.h): the same operations
// per lane, so the same bits. Two groups at a time: each group is a serial chain of
// multiply-adds (latency-bound), so two chains interleave; the longer group's first
// slots run alone. (GroupSlot is 32-byte aligned: a slot's c and absC loads never
// straddle a cache line.)
ALGRAY_TARGET_BEGIN("avx2")
typedef double V4 __attribute__((vector_size(32)));

template <class GroupSlot>
inline void zStep(const GroupSlot* s, V4 zz, V4 azz, V4& q, V4& qz, V4& qa) {
  V4 c, a;
  std::memcpy(&c, s->c, sizeof c);
  std::memcpy(&a, s->absC, sizeof a);
  qz = qz * zz + q;
  q = q * zz + c;
  qa = qa * azz + a;
}

inline void storeRows(const std::uint16_t* lane, V4 q, V4 qz, V4 qa, double* rq, double* rqz,
                      double* rqa) {
  for (int l = 0; l < 4; ++l) {
    rq[lane[l]] = q[l];
    rqz[lane[l]] = qz[l];
    rqa[lane[l]] = qa[l];
  }
}

template <class GroupSlot>
__attribute__((noinline)) void zRowsAvx2(const GroupSlot* s, const std::uint16_t* lane,
                                         std::span<const std::uint8_t> groupLength, double z,
                                         double* rq, double* rqz, double* rqa) {
  const double az = std::abs(z);
  const V4 zz = {z, z, z, z}, azz = {az, az, az, az};
  const V4 zero = {0.0, 0.0, 0.0, 0.0};
  std::size_t g = 0;
  for (; g + 1 < groupLength.size(); g += 2) {
    const int la = groupLength[g], lb = groupLength[g + 1];
    const GroupSlot* sa = s;
    const GroupSlot* sb = s + la;
    V4 qA = zero, qzA = zero, qaA = zero, qB = zero, qzB = zero, qaB = zero;
    for (int k = lb; k < la; ++k) zStep(sa++, zz, azz, qA, qzA, qaA);
    for (int k = la; k < lb; ++k) zStep(sb++, zz, azz, qB, qzB, qaB);
    for (const GroupSlot* end = sb + std::min(la, lb); sb != end; ++sa, ++sb) {
      zStep(sa, zz, azz, qA, qzA, qaA);
      zStep(sb, zz, azz, qB, qzB, qaB);
    }
    storeRows(lane, qA, qzA, qaA, rq, rqz, rqa);
    storeRows(lane + 4, qB, qzB, qaB, rq, rqz, rqa);
    s = sb;
    lane += 8;
  }
  if (g < groupLength.size()) {
    V4 q = zero, qz = zero, qa = zero;
    for (const GroupSlot* end = s + groupLength[g]; s != end; ++s) zStep(s, zz, azz, q, qz, qa);
    // The spare lanes of a short last group repeat its last row: stored in lane order,
    // the real row's own value lands last either way (the same value).
    storeRows(lane, q, qz, qa, rq, rqz, rqa);
  }
}
ALGRAY_TARGET_END
#endif

// The nested scheme over a box in row groups (HornerForm::evaluate, which explains it) at
// (x, y, z): the value, the three partial derivatives and the magnitude scheme's value.
struct Nested {
  double f, fx, fy, fz, fa;
};

template <class Groups>
__attribute__((always_inline)) inline Nested nestedHorner(const Groups& g, double x, double y,
                                                          double z) {
  // Horner with derivatives: (v, dv) <- (v t + c, dv t + v) is v(t) and v'(t) of the level
  // polynomial (Higham, Alg. 5.2 with k = 1); the y- and z-derivatives of the inner levels
  // are carried as coefficients of the outer ones. The *a variables run the bound's scheme.
  //
  // The z-rows run four at a time, in the lanes of two 2-double vectors or one AVX one
  // (the rows are independent; only the y-level below joins them, in their order). Each
  // lane does what the one-row loop did, bit for bit: a padding slot (0, 0) before a row's
  // first one leaves q = q' = q_a = +0 (0 z + 0 = +-0, and -0 + 0 = +0; an inf or NaN z
  // gives NaN there as the row's own first step 0 z does), and the first real slot then
  // sets q = c exactly as 0 z + c did. (The padding carries no underflow floor: q_a stays
  // 0.)
  // Why: a row is a serial chain of multiply-adds, latency-bound, and the polish
  // evaluates f at every hit. Measured (AMD EPYC Zen 3, 16384 points, ns per evaluation):
  // Sarti's dodecic (167 slots) 216 -> 173, the Barth sextic (33) 49.7 -> 43.2; primary
  // rays (128x128, one thread) 1.2 % and 1.0 % faster. Not kept: adjacent rows two to a
  // vector (no gain: an even polynomial's long rows alternate with zero rows of one slot,
  // so each pair was as long as its long row), eight rows a group (179-183 and 50 ns), and
  // compile-time row lengths (unrolled per length, no gain or slower: the loop's exits
  // were predicted).
  // With AVX2 (core_isa.h) the four lanes are one register and two groups run
  // interleaved (zRowsAvx2): polynomial_bench BM_EvalNew, medians of interleaved runs,
  // ns: Sarti 173 -> 149, Barth sextic 43.4 -> 40.6, dense degree 20 1110 -> 785. (One
  // group at a time: 155, 40.0 and 913.) Not kept: the y-levels of four x-blocks in the
  // lanes too (blocks grouped and padded at their start like the rows, each lane's row
  // results gathered per position): Sarti 146 -> 162, Barth sextic 40.5 -> 55.4 (same
  // session).
  constexpr std::size_t kMaxRows = (kMaxDegree + 1) * (kMaxDegree + 2) / 2;
  double rq[kMaxRows], rqz[kMaxRows], rqa[kMaxRows];
#if ALGRAY_CORE_AVX2
  if (core_isa::active() == core_isa::Isa::kAvx2)
    zRowsAvx2(g.slots.data(), g.rows.data(), g.length, z, rq, rqz, rqa);
  else
#endif
    zRows(g.slots.data(), g.rows.data(), g.length, z, rq, rqz, rqa);
  const double ax = std::abs(x), ay = std::abs(y);
  double f = 0.0, fx = 0.0, fy = 0.0, fz = 0.0, fa = 0.0;
  std::size_t r = 0;
  for (const std::uint8_t blockRows : g.blockRows) {
    double b = 0.0, by = 0.0, bz = 0.0, ba = 0.0;
    for (const std::size_t end = r + blockRows; r != end; ++r) {
      by = by * y + b;
      b = b * y + rq[r];
      bz = bz * y + rqz[r];
      ba = ba * ay + rqa[r];
    }
    fx = fx * x + f;
    f = f * x + b;
    fy = fy * x + by;
    fz = fz * x + bz;
    fa = fa * ax + ba;
  }
  return {f, fx, fy, fz, fa};
}

}  // namespace

void HornerForm::buildBox(const Polynomial& f, int m, std::vector<Slot>& slots,
                          std::vector<std::uint8_t>& rowLength,
                          std::vector<std::uint8_t>& blockRows) {
  // Highest i with a non-zero block, highest j per block, highest k per row: the box.
  int topI = 0;
  for (int i = 0; i <= m; ++i)
    for (int j = 0; i + j <= m; ++j)
      for (int k = 0; i + j + k <= m; ++k)
        if (f.coeff(i, j, k) != 0.0) topI = std::max(topI, i);
  for (int i = topI; i >= 0; --i) {
    int topJ = 0;
    for (int j = 0; i + j <= m; ++j)
      for (int k = 0; i + j + k <= m; ++k)
        if (f.coeff(i, j, k) != 0.0) topJ = std::max(topJ, j);
    // Every block keeps at least one row and every row one slot (possibly a zero
    // coefficient): the multiplication by x (or y) that passes it can underflow, and its
    // slot must carry kUnderflowFloor.
    blockRows.push_back(static_cast<std::uint8_t>(topJ + 1));
    for (int j = topJ; j >= 0; --j) {
      int topK = 0;
      for (int k = 0; i + j + k <= m; ++k)
        if (f.coeff(i, j, k) != 0.0) topK = k;
      rowLength.push_back(static_cast<std::uint8_t>(topK + 1));
      for (int k = topK; k >= 0; --k) {
        const double c = f.coeff(i, j, k);
        slots.push_back({c, std::abs(c) + kUnderflowFloor});
      }
    }
  }
}

HornerForm::Groups HornerForm::buildGroups(std::span<const Slot> slots,
                                           std::span<const std::uint8_t> rowLength,
                                           std::span<const std::uint8_t> blockRows) {
  // The rows in groups of four of similar length (evaluate): row starts in slots, the
  // rows by decreasing length (ties in order), then each group's padded positions. A
  // group short of four rows repeats its last row in the spare lanes (computed twice,
  // stored once more: the same value).
  Groups out;
  out.blockRows.assign(blockRows.begin(), blockRows.end());
  const std::size_t rows = rowLength.size();
  std::vector<std::size_t> start(rows + 1, 0);
  for (std::size_t r = 0; r < rows; ++r) start[r + 1] = start[r] + rowLength[r];
  std::vector<std::uint16_t> order(rows);
  for (std::size_t r = 0; r < rows; ++r) order[r] = static_cast<std::uint16_t>(r);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint16_t a, std::uint16_t b) { return rowLength[a] > rowLength[b]; });
  for (std::size_t g0 = 0; g0 < rows; g0 += 4) {
    std::uint16_t lane[4];
    for (std::size_t l = 0; l < 4; ++l) lane[l] = order[std::min(g0 + l, rows - 1)];
    const int len = rowLength[lane[0]];
    out.length.push_back(static_cast<std::uint8_t>(len));
    for (const std::uint16_t r : lane) out.rows.push_back(r);
    for (int k = 0; k < len; ++k) {
      GroupSlot p{{0.0, 0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 0.0}};
      for (int l = 0; l < 4; ++l) {
        const int lenL = rowLength[lane[l]];
        if (k < len - lenL) continue;
        const Slot& slot = slots[start[lane[l]] + static_cast<std::size_t>(k - (len - lenL))];
        p.c[l] = slot.c;
        p.absC[l] = slot.absC;
      }
      out.slots.push_back(p);
    }
  }
  return out;
}

HornerForm::HornerForm(const Polynomial& f) : degree_(f.degree()) {
  // The zero polynomial is stored as one zero coefficient, so that it too turns a
  // non-finite point into NaN (0 * inf) instead of a clean 0.
  const int m = std::max(degree_, 0);
  const double g = gamma(2 * m + 3);
  errorFactor_ = g / (1.0 - g) * kSlack;
  std::vector<std::uint8_t> ownBlockRows;  // kept in groups_ (blockRows())
  buildBox(f, m, slots_, rowLength_, ownBlockRows);
  for (const Slot& s : slots_) {
    signedTerms_.push_back({s.c, std::abs(s.c)});
    absCoeffSum_ += std::abs(s.c);
  }
  groups_ = buildGroups(slots_, rowLength_, ownBlockRows);

  // ---- Even axes: f(x, y, z) = F(x^2, y, z) etc. (evaluate, "Even axes") ----
  // An axis is even when every non-zero monomial has an even exponent in it, and
  // worth halving when some exponent is not 0.
  bool odd[3] = {false, false, false};
  int top[3] = {0, 0, 0};
  for (int n = 0; n <= degree_; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      if (f.coeffs()[idx] == 0.0) return;
      const int e[3] = {i, j, k};
      for (int a = 0; a < 3; ++a) {
        odd[a] = odd[a] || e[a] % 2 != 0;
        top[a] = std::max(top[a], e[a]);
      }
    });
  for (int a = 0; a < 3; ++a) {
    axisDegree_[a] = top[a];
    if (!odd[a] && top[a] > 0) evenAxes_ |= 1u << a;
  }
  if (evenAxes_ == 0) return;
  auto isEven = [&](int a) { return (evenAxes_ >> a & 1u) != 0; };
  Polynomial reduced;
  for (int n = 0; n <= degree_; ++n)
    forEachMonomialOfDegree(n, [&](int i, int j, int k, int idx) {
      const double c = f.coeffs()[idx];
      if (c != 0.0)
        reduced.setCoeff(isEven(0) ? i / 2 : i, isEven(1) ? j / 2 : j, isEven(2) ? k / 2 : k, c);
    });
  std::vector<Slot> slots;
  std::vector<std::uint8_t> rowLength, blockRows;
  buildBox(reduced, std::max(reduced.degree(), 0), slots, rowLength, blockRows);
  reduced_ = buildGroups(slots, rowLength, blockRows);
  for (const Slot& s : slots) evenTerms_.push_back({s.c, std::abs(s.c)});
  evenRowLength_ = rowLength;
  restrictEven_ = degree_ >= 4;
  // N: the most roundings on any slot (a, b, c) of F's box, 3a + 1 on an even axis and
  // 2a + 1 on the others (derivation in evaluate).
  int roundings = 0;
  std::size_t row = 0;
  int a = static_cast<int>(blockRows.size()) - 1;
  auto count = [&](int axis, int e) { return isEven(axis) ? 3 * e + 1 : 2 * e + 1; };
  for (const std::uint8_t rows : blockRows) {
    for (int b = rows - 1; b >= 0; --b, ++row)
      roundings = std::max(roundings, count(0, a) + count(1, b) + count(2, rowLength[row] - 1));
    --a;
  }
  const double gN = gamma(roundings);
  reducedMagFactor_ = (1.0 + 0x1p-50) / (1.0 - gN);
  reducedErrorFactor_ = gN * kSlack;
  // The exponent fields (biased) a coordinate may have on the reduced path: on an even
  // axis 2^-400 <= |x| < 2^401 (x^2 normal and finite, far from both ends), on the others
  // any normal number; +-0 everywhere.
  for (int axis = 0; axis < 3; ++axis) {
    reducedExpLo_[axis] = isEven(axis) ? 1023 - 400 : 1;
    reducedExpSpan_[axis] = isEven(axis) ? 800 : 2045;
  }
}

Polynomial::Evaluation HornerForm::evaluate(const glm::dvec3& p) const {
  // The even form (evaluateReduced) out of line, f's own box inlined here as before: with
  // nestedHorner called from both paths (out of line, or inlined twice: two scratch
  // frames), a polynomial with no even axis measured 4-5 % slower (polynomial_bench,
  // medians of 5 interleaved pairs: dense degree 10 172 -> 180 ns, 20 805 -> 834); as
  // here, 168 -> 169 and 782 -> 785 (7 pairs).
  if (evenAxes_ != 0 && reducedApplies(p)) [[likely]]
    return evaluateReduced(p);
  Polynomial::Evaluation e;
  const double x = p.x, y = p.y, z = p.z;
  const double ax = std::abs(x), ay = std::abs(y), az = std::abs(z);
  const Nested n = nestedHorner(groups_, x, y, z);
  e.value = n.f;
  e.gradient = {n.fx, n.fy, n.fz};
  e.magnitude = n.fa;
  e.valueError = errorFactor_ * n.fa;
  // A subnormal coordinate reads as 0 under DAZ, in the value and in the magnitudes: the
  // result is f at a point moved by eps < 2^-1022 per coordinate, which differs from
  // f(p) by at most m sum|c| 2^-1022 max(1, |p_i|)^(m-1) (telescoped over the factors of
  // each monomial, as taylor.cpp's floor): added, doubled, in that case only.
  if (ray_horner::hasSubnormal(p)) [[unlikely]] {
    const int a = ray_horner::ceilExponent(std::max({ax, ay, az}));
    const int m = std::max(degree_, 1);
    e.valueError += 2.0 * m * absCoeffSum_ * ray_horner::pow2(a * (m - 1) - 1022);
  }
  return e;
}

// ---- Even axes ----
// When every exponent of x is even, f(x, y, z) = F(X, y, z) with X = x^2, and F has half
// the x-degree: the box of F has about half the x-blocks (and likewise for y, z-rows for
// z), where f's own box carries the zero odd blocks, rows and slots and spends a
// multiply-add on each. Slots in the two boxes: Sarti's dodecic 167 and 84, the Barth sextic
// 33 and 17, Chmutov-16 49 and 25 (HornerFormEvenAxes.DetectedPerAxis prints the gallery).
//
// Bound. Write a slot of F's box as (a, b, c), its coefficient C, its monomial in f
// x^{e_x a} y^{e_y b} z^{e_z c} with e = 2 on an even axis and 1 on the others. On an
// even axis the input is X^ = fl(x^2) = x^2 (1 + delta), |delta| <= u, exactly when
// x^2 is normal and finite (2^-400 <= |x| < 2^401 below; x = +-0 gives X^ = 0 exactly),
// so X^a = x^{2a} (1 + theta_a) (Higham, Lemma 3.1). The nested Horner scheme on F at
// the computed inputs puts (2a+1) + (2b+1) + (2c+1) roundings on C (see the top), so the
// computed value is sum C x^{e_x a} y^{e_y b} z^{e_z c} (1 + theta_n) with
// n = sum over the axes of 3a + 1 on an even axis and 2a + 1 on the others, and
//   |computed - f| <= gamma_N E,   E = sum |C| |x|^{e_x a} |y|^{e_y b} |z|^{e_z c},
// N the largest n over the box (the constructor; n <= the 2m + 3 of f's own box, since
// 3a + 1 <= 2 (2a) + 1). E is f's own magnitude (the same terms). The magnitude scheme
// runs on |C| and the same inputs, so its computed value is >= (1 - gamma_N) E and
//   magnitude = Ê (1 + 2^-50) / (1 - gamma_N) >= E
// (the 2^-50 covers the roundings of that product and factor, and the magnitude
// scheme's own underflow etas, each < 2^-56 of the floor 2^-966 carried by its slot);
// valueError = gamma_N kSlack magnitude >= gamma_N E. Underflow in the scheme on F is
// covered by the floor in F's slots exactly as on f's box (the inputs X^ are doubles
// like any other). The reduced path takes no subnormal input (so DAZ changes nothing)
// and no NaN or inf: those, and an even coordinate whose square would underflow or
// overflow, run f's own box (whose rules hold for every input).
//
// Gradient: df/dx = 2 x F_X(X^) on an even axis (the chain rule; 2 x is exact), F_X from
// the same derivative recurrences; it needs no bound, and its terms carry at most
// N + 1 roundings, about those of f's own box.
//
// Measured (AMD EPYC Zen 3, AVX2; polynomial_bench BM_EvalNew, ns, medians of 7
// interleaved pairs): Sarti's dodecic 147 -> 71.3, Barth decic 96.4 -> 51.0, Chmutov-16
// 110 -> 56.5, Endrass octic 77.4 -> 42.7, Barth sextic 41.0 -> 27.0, torus 33.8 -> 25.8,
// Kummer (x, y even) 33.8 -> 26.6; SSE2 kernels: Sarti 177 -> 84.5. speed_report, one
// thread, Mrays/s, medians of 8 pairs: Sarti primary 0.958 -> 1.02, shadow 0.847 -> 0.930
// (shadow rays evaluate f at their origin on the surface); Barth sextic primary
// 3.01 -> 3.03, shadow 2.29 -> 2.34. Not kept: four row groups interleaved in zRowsAvx2
// instead of two (Sarti 71.3 -> 76.6 ns, dense degree 10 172 -> 182, 5 pairs).
__attribute__((noinline)) Polynomial::Evaluation HornerForm::evaluateReduced(
    const glm::dvec3& p) const {
  const double sq[3] = {p.x * p.x, p.y * p.y, p.z * p.z};
  double q[3];
  for (int a = 0; a < 3; ++a) q[a] = (evenAxes_ >> a & 1u) != 0 ? sq[a] : p[a];
  const Nested n = nestedHorner(reduced_, q[0], q[1], q[2]);
  // The chain rule: d/dx F(x^2) = 2 x F_X(x^2).
  const double d[3] = {n.fx, n.fy, n.fz};
  Polynomial::Evaluation e;
  e.value = n.f;
  for (int a = 0; a < 3; ++a) e.gradient[a] = (evenAxes_ >> a & 1u) != 0 ? 2.0 * p[a] * d[a] : d[a];
  e.magnitude = reducedMagFactor_ * n.fa;
  e.valueError = reducedErrorFactor_ * e.magnitude;
  return e;
}

// ---- Compensated value ----------------------------------------------------------------
namespace {

// a + b = s + err exactly (Knuth's TwoSum).
inline double twoSum(double a, double b, double& err) {
  const double s = a + b, bb = s - a;
  err = (a - (s - bb)) + (b - bb);
  return s;
}

// a b = p + err exactly, without FMA (Dekker's TwoProduct with Veltkamp's split: the core
// is built without contraction, so the same bits on every host), valid for |a|, |b| below
// 2^995 (the split's 2^27 + 1 times them stays finite) and products above the underflow
// range (below it err loses bits; the compensation then only helps less).
inline double twoProduct(double a, double b, double& err) {
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const double ca = kSplit * a, ah = ca - (ca - a), al = a - ah;
  const double cb = kSplit * b, bh = cb - (cb - b), bl = b - bh;
  const double p = a * b;
  err = al * bl - (((p - ah * bh) - al * bh) - ah * bl);
  return p;
}

// One compensated Horner step: (v, e) <- (v x + c, e x + (pi + sigma + ec)), where v x =
// prod + pi and prod + c = v' + sigma exactly, and ec is c's own error term (the inner
// level's): the running value plus its first-order correction (Graillat et al., Alg. 3.2).
inline void compensatedStep(double& v, double& e, double x, double c, double ec) {
  double pi, sigma;
  const double prod = twoProduct(v, x, pi);
  v = twoSum(prod, c, sigma);
  e = e * x + (pi + sigma + ec);
}

}  // namespace

// Underflow. Graillat et al.'s bound assumes that no operation underflows. One that does
// errs by an absolute amount below 2^-1022 (below 2^-1075 with gradual underflow; under
// flush-to-zero a result below 2^-1022 becomes 0, and under denormals-are-zero a
// subnormal slot or partial reads as 0, the same loss). A compensated step runs 23
// operations (two splits of 3, TwoProduct's 5 products and 4 sums, TwoSum's 6, the error
// update's 3, counted 32); what one of them loses at the step of slot (i, j, k) (or of the
// row or block that ends there) reaches the result multiplied by |x|^i |y|^j |z|^k, at most
// P = prod over the axes of max(1, |p_a|)^(f's degree in a). The steps are one per slot,
// row and block, at most 3 per slot: U = 96 N 2^-1022 P for N slots (P rounded up to a
// power of two), below 2^-700 for |p_a| up to 2^8 at degree 40. A subnormal coordinate
// read as 0 under DAZ moves f by at most m sum|c| 2^-1022 P per axis (as
// HornerForm::evaluate), added doubled.
double HornerForm::compensatedBound(double v, double magnitude, const glm::dvec3& p) const {
  const double g = gamma(2 * degree_ + 6);
  int e = -1022;
  for (int a = 0; a < 3; ++a) e += ray_horner::ceilExponent(std::abs(p[a])) * axisDegree_[a];
  const double scale = ray_horner::pow2(e);
  double underflow = 96.0 * static_cast<double>(slots_.size()) * scale;
  if (ray_horner::hasSubnormal(p)) [[unlikely]]
    underflow += 6.0 * std::max(degree_, 1) * absCoeffSum_ * scale;
  return 2.0 * kUnitRoundoff * std::abs(v) + g * g * magnitude + underflow;
}

double HornerForm::valueCompensated(const glm::dvec3& p) const {
  // The box of evaluate(), one row at a time: z-rows (k descending), folded into their
  // x-block by y (j descending), the blocks by x (i descending); each level carries the
  // error terms of the one inside it.
  constexpr double kRange = 0x1p995;
  if (!(std::abs(p.x) < kRange && std::abs(p.y) < kRange && std::abs(p.z) < kRange))
    return std::numeric_limits<double>::quiet_NaN();
  const std::span<const std::uint8_t> rows = groups_.blockRows;
  std::size_t s = 0, r = 0;
  double vx = 0, ex = 0;
  bool inRange = true;
  for (const std::uint8_t blockRowCount : rows) {
    double vy = 0, ey = 0;
    for (int jr = 0; jr < blockRowCount; ++jr, ++r) {
      double vz = 0, ez = 0;
      for (int k = 0; k < rowLength_[r]; ++k, ++s) {
        compensatedStep(vz, ez, p.z, slots_[s].c, 0.0);
        inRange &= std::abs(vz) < kRange;
      }
      compensatedStep(vy, ey, p.y, vz, ez);
      inRange &= std::abs(vy) < kRange;
    }
    compensatedStep(vx, ex, p.x, vy, ey);
    inRange &= std::abs(vx) < kRange;
  }
  const double value = vx + ex;
  return inRange && std::isfinite(value) ? value : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace algray
