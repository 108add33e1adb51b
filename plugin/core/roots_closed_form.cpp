// Closed forms for degrees 1 and 2, inside the same monotone-piece sweep as the
// iterative solvers (roots_scan.h), so that the tangent and endpoint rules are the same
// for every degree. The vertex of the parabola is the only critical point; the roots
// come from the cancellation-free quadratic formula with an FMA-accurate discriminant
// (roots_detail.h), and a root that the formula places outside its piece (possible only
// when the discriminant is at rounding level) falls back to the bracketed Newton.
//
// Degrees 3 and 4 go to Yuksel's recursion, which ends in this same quadratic (for a
// cubic: the vertex pair of g' in closed form, then one bracketed Newton per monotone
// piece); cubic/quartic closed forms (Flocke, TOMS 954; Orellana and De Michele, TOMS
// 1010) are not implemented yet, so that comparison is still open.
#include "roots_detail.h"
#include "roots_scan.h"

namespace algray::roots_detail {

template <class T>
int solveClosedForm(const LocalPoly<T>& g, Query q, T tol, LocalRoot<T>* out, int maxOut) {
  if (g.n < 1 || maxOut < 1) return 0;
  if (g.n > 2) return solveYuksel(g, q, tol, out, maxOut);
  const T* c = g.c.data();
  if (g.n == 1) {
    auto piece = [&](T a, T b, T fa, T fb) {
      const T r = -c[0] / c[1];
      return (r > a && r < b) ? r : newtonInBracket(c, g.noise.data(), Deg<1>{}, a, b, fa, fb, tol);
    };
    return scanPieces(g, Deg<1>{}, static_cast<const T*>(nullptr), 0, q, piece, out, maxOut);
  }
  // Degree 2: the vertex -c1 / (2 c2) splits the interval into two monotone pieces.
  T crit[1];
  const T vertex = -c[1] / (2 * c[2]);
  const int nCrit = (vertex > g.lo && vertex < g.hi) ? 1 : 0;
  crit[0] = vertex;
  T r[2];
  const int nr = quadraticRoots(c[2], c[1], c[0], r[0], r[1]);
  auto piece = [&](T a, T b, T fa, T fb) {
    for (int i = 0; i < nr; ++i)
      if (r[i] > a && r[i] < b) return r[i];
    return newtonInBracket(c, g.noise.data(), Deg<2>{}, a, b, fa, fb, tol);
  };
  return scanPieces(g, Deg<2>{}, crit, nCrit, q, piece, out, maxOut);
}

template int solveClosedForm<double>(const LocalPoly<double>&, Query, double,
                                     LocalRoot<double>*, int);
template int solveClosedForm<float>(const LocalPoly<float>&, Query, float, LocalRoot<float>*,
                                    int);

}  // namespace algray::roots_detail
