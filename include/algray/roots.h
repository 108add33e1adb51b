#pragma once
// Real roots of a univariate polynomial g(s) = sum c[i] s^i in an interval: the first
// root (closest hit), whether any root exists (occlusion), and all roots in order.
// Independent of Embree; no heap allocation. See plugin/core/roots*.cpp for the methods
// and their references: the quadratic formula for degree <= 2, Yuksel's HPG 2022
// critical-point splitting above (with a Taylor exclusion test that cuts its recursion
// on short intervals); closed-form cubic and quartic solvers (in the manner of Flocke's
// TOMS 954 and Orellana and De Michele's TOMS 1010, each root polished by Newton), which
// measured as accurate as Yuksel at degrees 3-4 and no faster; and a Sturm-sequence and a
// Bernstein subdivision solver kept for comparison (tests/bench/roots_report.cpp,
// tests/bench/roots_bench.cpp, docs/roots-summary.md).
//
// The contract (Auto, ClosedForm, Yuksel; the interval rules also Sturm and Bernstein;
// roots_scan.h has the derivation):
//  * Interval (lo, hi]: a root within the rounding noise of lo is taken to be lo and is not
//    reported, so calling again with lo = the previous root gives the next root (never the
//    same one twice, tangent or not); a root within noise of hi is reported as hi, so two
//    intervals sharing an endpoint report a root on it exactly once.
//  * Tangent roots: at a local extremum s* of g where |g(s*)| <= sum_i (err[i] +
//    gamma(2 deg + 1) |c[i]|) |s*|^i, s* is reported as a root (grazing hits are kept;
//    near misses within that bound are reported too).
//  * Exact zeros: where c[0] .. c[k-1] are 0 and their error bounds 0, g = s^k h exactly;
//    0 is reported (if in the interval) and h's roots are found in h's own frame, so roots
//    of h far closer to 0 than the interval's scale stay apart from it.
//  * Range: where g's terms over the interval span more binades than one frame holds
//    (roots near 1 and 1e8 at degree 40), the interval is solved in pieces by magnitude,
//    each in its own frame (roots.cpp, rangeSplit), so no root is lost below the range.
//    Roots below T's normal range (subnormal) are found to T's absolute grid there (one
//    unit of 2^-1074 in double), and the noise at lo includes that grid, so a walk from such
//    an answer does not find its root again.
//  * Accuracy: a simple root to within a few u cond(r), cond(r) = sum|c_i||r|^i / |g'(r)|
//    (measured worst case 1.22 u cond against the exact root over 781 roots in
//    tests/roots_test.cpp, which prints it, 1.42-2.17 with six other draws of its seeds;
//    2.01 over 1587 roots on spans around 0).
//  * Cost: bounded; non-finite coefficients, error bounds or interval ends give "no root".
// Sturm and Bernstein exist to be measured against: they follow the interval rules (a
// noise-level end is moved inwards past its noise region first, roots_scan.h), report
// even-multiplicity roots only where they isolate them, and are accurate only relative to
// the interval (Bernstein) or for roots not far below its length (Sturm, whose counts such
// roots can also spoil for the others, and which above degree 20 can lose roots of
// conditioning 1e8 and more, roots_sturm.cpp); a walk with them can return a root a second
// time within that accuracy past the first answer.
#include "algray/polynomial.h"  // kMaxDegree, Error

#include <optional>
#include <span>

namespace algray {

enum class RootMethod {
  Auto,        // the measured winner per degree: closed form <= 2, else Yuksel (at 3-4
               // a near tie, see roots.cpp)
  ClosedForm,  // degrees 1..4 in closed form always; higher degrees use Yuksel
  Yuksel,      // recursive critical points + safeguarded Newton
  Sturm,       // Sturm sequence isolation + bisection/Newton (POV-Ray style); double only
  Bernstein,   // Bernstein/Descartes subdivision; double only
};

// Whether m is one of RootMethod's enumerators (the solvers and SurfaceDesc refuse others).
constexpr bool validRootMethod(RootMethod m) {
  return m == RootMethod::Auto || m == RootMethod::ClosedForm || m == RootMethod::Yuksel ||
         m == RootMethod::Sturm || m == RootMethod::Bernstein;
}

// Whether t is a RootOptions::relTolerance the solvers take: in [0, 1] (not NaN).
constexpr bool validRelTolerance(double t) { return t >= 0.0 && t <= 1.0; }

struct RootOptions {
  RootMethod method = RootMethod::Auto;
  // Relative tolerance on a root, relative to the interval length, in [0, 1] (else the
  // solvers throw Error); 0 means full precision (iterate until the root is bracketed to
  // adjacent doubles or Newton stalls). Auto, Yuksel and ClosedForm still report every
  // root, each within the tolerance of a sign change of g (the critical points that
  // separate roots are found to full precision whatever it is); a walk from such an answer,
  // firstRoot(c, err, answer, hi), can meet the same root again. The comparison solvers
  // (Sturm, Bernstein) can lose roots closer together than the tolerance.
  double relTolerance = 0.0;
  // The interval is (lo, hi]: a root within noise of lo is the one a caller walking the
  // roots already has (firstRoot(c, err, previousRoot, hi)), and is not reported. With
  // closedLo it is reported (at the extremum of |g| near lo, or lo itself): for an lo
  // that bounds a region rather than follows a root. The noise region of an m-fold root
  // is about u^(1/m) of the scale wide, so without it a multiple root that close to lo
  // is lost (the plugin solves on the clip region's span with closedLo).
  bool closedLo = false;
  // For solveFirstRoot with atNoise: atNoise is also set where g is within its noise bound
  // somewhere before the root by more than 2^-20 of the interval, on the monotone piece (or
  // subdivision node) that holds the root (then the root returned may be that point:
  // plugin/core/roots_scan.h, noiseBefore). The data of g cannot tell whether the exact
  // function has roots there, so a caller that checks noise-rule roots on it should look
  // there too (the Embree adapter does). Costs an evaluation of g a solve. Pieces before
  // that one hold no sign change and no critical point within noise, and are proved clear
  // at their ends only: where the noise bound grows across such a piece faster than |g|
  // (a large error on a high power), g can come within it inside, unflagged.
  bool noiseBefore = false;
};

// c has degree+1 <= kMaxDegree+1 entries (more throws Error, as do options outside their
// ranges: a method that is no RootMethod, relTolerance NaN or outside [0, 1]); c[degree]
// may be rounding noise: leading coefficients negligible against the others, by the rule
// documented in roots.cpp, are dropped. err, if not empty, has the same size (else Error)
// and bounds the absolute error of each c[i]; it enters the noise bound of the tangent and
// end rules above. Non-finite input gives "no root", never a hang.
//
// solveFirstRoot is firstRoot's answer as a flag and an out-parameter (true and root = the
// first root, or false); firstRoot is it, inline. (A std::optional<double> returned by a
// compiled function goes through memory with GCC 12: its flag is stored as a byte and
// read back as 8, a store-forwarding stall of ~4 ns on every call, 5-8 % of a cell-sized
// solve of degree 4-8; inline, the optional stays in registers.)
bool solveFirstRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
                    double& root, const RootOptions& options = {});
inline std::optional<double> firstRoot(std::span<const double> c, std::span<const double> err,
                                       double lo, double hi, const RootOptions& options = {}) {
  double root;
  if (!solveFirstRoot(c, err, lo, hi, root, options)) return std::nullopt;
  return root;
}
// The same, and whether the root came from the noise rules above (a tangent or grazing
// point, or an end within noise: g's data cannot tell it from a near miss) rather than
// from a sign change of g, which proves a root within g's noise region about it. A caller
// that can evaluate its function more accurately than g's error bound allows may check
// such a root (the Embree adapter does: plugin/embree/ray_settle.cpp).
bool solveFirstRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
                    double& root, bool& atNoise, const RootOptions& options = {});
bool hasRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
             const RootOptions& options = {});
// Writes the roots in increasing order (each multiple root once) into out and returns how
// many there are (at most out.size()).
int allRoots(std::span<const double> c, std::span<const double> err, double lo, double hi,
             std::span<double> out, const RootOptions& options = {});

// The same as firstRoot for a quadratic (c[2] != 0) in the caller's frame, for hot
// loops (the plugin's quadric path): bitwise the same answer, without the frame mapping;
// coefficients, bounds or interval ends outside a safe range go to firstRoot.
bool solveFirstRootQuadratic(std::span<const double, 3> c, std::span<const double, 3> err,
                             double lo, double hi, double& root);
inline std::optional<double> firstRootQuadratic(std::span<const double, 3> c,
                                                std::span<const double, 3> err, double lo,
                                                double hi) {
  double root;
  if (!solveFirstRootQuadratic(c, err, lo, hi, root)) return std::nullopt;
  return root;
}

// Float variants, kept for the speed/error comparison (same algorithms in float; Sturm and
// Bernstein fall back to Auto). Measured: float's rounding bound is so wide above degree
// ~4 that the tangent rule reports many near misses as hits; see docs/roots-summary.md.
bool solveFirstRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
                    float& root, const RootOptions& options = {});
bool solveFirstRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
                    float& root, bool& atNoise, const RootOptions& options = {});
inline std::optional<float> firstRoot(std::span<const float> c, std::span<const float> err,
                                      float lo, float hi, const RootOptions& options = {}) {
  float root;
  if (!solveFirstRoot(c, err, lo, hi, root, options)) return std::nullopt;
  return root;
}
bool hasRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
             const RootOptions& options = {});
int allRoots(std::span<const float> c, std::span<const float> err, float lo, float hi,
             std::span<float> out, const RootOptions& options = {});

}  // namespace algray
