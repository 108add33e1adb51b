// solveFirstRootQuadratic (roots.h, firstRootQuadratic): the closed-form quadratic of
// roots_closed_form.cpp and the sweep of roots_scan.h in the caller's frame, for the plugin's
// quadric path, where the general entry point's frame mapping (exponent extraction and power-of-two
// scaling of every coefficient) cost as much as the solve itself (perf on the speed report's
// sphere: toLocal 11 % of the run, the solve 5 %).
//
// Why the result is the same as firstRoot's: the local frame is an exact power-of-two
// scaling of s and of g, so every comparison of the sweep (|g| against its noise bound,
// signs) and every Newton step gives the same answer in either frame as long as nothing
// overflows or underflows; the range check below keeps the coefficients and the powers
// of the interval ends far from both. The rule that drops a leading coefficient as
// rounding noise is applied in the same form; a quadratic it would drop goes to
// firstRoot, as do anything outside the range and an exact root at 0 (c0 = 0 with no
// error, which firstRoot factors out).
#include "algray/roots.h"

#include "roots_detail.h"

#include <array>
#include <cmath>

namespace algray {

bool solveFirstRootQuadratic(std::span<const double, 3> c, std::span<const double, 3> err,
                             double lo, double hi, double& root) {
  auto inRange = [](double x) {
    return x == 0.0 || (std::abs(x) >= 1e-100 && std::abs(x) <= 1e100);
  };
  const double scale = std::max(std::abs(lo), std::abs(hi));
  bool safe = std::isfinite(lo) && std::isfinite(hi) && lo < hi && scale <= 1e30 && c[2] != 0.0;
  for (int i = 0; i < 3 && safe; ++i)
    safe = inRange(c[i]) && inRange(err[i]) && std::isfinite(err[i]);
  // An exact root at 0 (c0 = 0 with no error) is factored out by firstRoot (roots.cpp): the
  // closed form here could put it in one noise cluster with the other root.
  safe = safe && (c[0] != 0.0 || err[0] != 0.0);
  // The drop rule of toLocal (roots.cpp) in the caller's frame: |c2| S^2 against
  // u max(|c0|, |c1| S) and against the caller's own bound on c2 (S = max(|lo|, |hi|)
  // here, the next power of two there: a quadratic near the rule's threshold goes to
  // firstRoot, which decides it exactly as before).
  if (safe) {
    const double lead = std::abs(c[2]) * scale * scale;
    const double lower = std::max(std::abs(c[0]), std::abs(c[1]) * scale);
    safe = lead > 4.0 * roots_detail::kUnit<double> * lower && std::abs(c[2]) > 2.0 * err[2];
  }
  if (!safe)
    return solveFirstRoot(std::span<const double>(c), std::span<const double>(err), lo, hi, root);

  roots_detail::LocalPoly<double> g;
  g.n = 2;
  g.lo = lo;
  g.hi = hi;
  const double gEval = roots_detail::gammaT<double>(5);  // one Horner evaluation, n = 2
  for (int i = 0; i < 3; ++i) {
    g.c[i] = c[i];
    g.noise[i] = err[i] + gEval * std::abs(c[i]);
  }
  roots_detail::LocalRoot<double> r[1];
  if (roots_detail::solveClosedForm(g, roots_detail::Query::First, 0.0, r, 1) == 0) return false;
  root = r[0].v >= hi ? hi : r[0].v > lo ? r[0].v : std::nextafter(lo, hi);
  return true;
}

}  // namespace algray
