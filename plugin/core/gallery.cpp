// The gallery: classic algebraic surfaces written from their definitions with Polynomial
// arithmetic (not parsed from text, so the parser tests can compare against them).
// Coordinates: the affine chart w = 1 of the projective definitions. Clip radii frame the
// part people draw (tests/gallery_test.cpp checks that the surface crosses or fills it).
#include "algray/gallery.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace algray {

namespace {

const Polynomial& X() {
  static const Polynomial p = Polynomial::variable(0);
  return p;
}
const Polynomial& Y() {
  static const Polynomial p = Polynomial::variable(1);
  return p;
}
const Polynomial& Z() {
  static const Polynomial p = Polynomial::variable(2);
  return p;
}
Polynomial c(double v) { return Polynomial(v); }
Polynomial r2() { return X() * X() + Y() * Y() + Z() * Z(); }

constexpr double kPhi = std::numbers::phi;  // golden ratio (1 + sqrt 5) / 2

Polynomial sphere() { return r2() - c(1.0); }

// Semi-axes 1, 0.75, 0.5: x^2/a^2 + y^2/b^2 + z^2/c^2 = 1.
Polynomial ellipsoid() {
  return X().pow(2) + Y().pow(2) * (1.0 / (0.75 * 0.75)) + Z().pow(2) * (1.0 / (0.5 * 0.5)) -
         c(1.0);
}

// Torus about the z axis, tube centre radius R = 1, tube radius r = 0.4:
// (x^2 + y^2 + z^2 + R^2 - r^2)^2 = 4 R^2 (x^2 + y^2).
Polynomial torus() {
  const double R = 1.0, r = 0.4;
  return (r2() + c(R * R - r * r)).pow(2) - 4.0 * R * R * (X() * X() + Y() * Y());
}

// Clebsch diagonal cubic, x0 + ... + x4 = 0 = x0^3 + ... + x4^3 in P^4, in the affine
// S3-symmetric form popularised by Hunt, "The Geometry of some special Arithmetic
// Quotients" (1996), and the SURFER gallery: all 27 lines are real.
Polynomial clebschCubic() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  return 81.0 * (x.pow(3) + y.pow(3) + z.pow(3)) -
         189.0 * (x * x * y + x * x * z + y * y * x + y * y * z + z * z * x + z * z * y) +
         54.0 * x * y * z + 126.0 * (x * y + y * z + z * x) - 9.0 * r2() - 9.0 * (x + y + z) +
         c(1.0);
}

// Cayley's 4-nodal cubic: 4 (x0^3 + x1^3 + x2^3 + x3^3) = (x0 + x1 + x2 + x3)^3 with
// x3 = w = 1 (the SURFER "record_cayleycubic" with a = b = 1/2, times 4). Its gradient
// 12 xi^2 = 3 S^2 vanishes where every xi = +-S/2 with exactly one sign odd: the nodes
// (1,1,-1), (1,-1,1), (-1,1,1), (-1,-1,-1).
Polynomial cayleyCubic() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  return 4.0 * (x.pow(3) + y.pow(3) + z.pow(3) + c(1.0)) - (x + y + z + c(1.0)).pow(3);
}

// Steiner's Roman surface x^2 y^2 + y^2 z^2 + z^2 x^2 = r^2 x y z (r = 1), the image of
// (u:v:w) -> (vw, uw, uv) on the sphere; the real zero set also holds the three axes.
Polynomial romanSurface() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  return x * x * y * y + y * y * z * z + z * z * x * x - x * y * z;
}

// Kummer's quartic family (x^2+y^2+z^2-mu^2)^2 - lambda p q r s, lambda = (3mu^2-1)/(3-mu^2),
// with the tetrahedron planes p, q, r, s = 1 - z -+ sqrt2 x, 1 + z +- sqrt2 y (as in
// SURFER); mu^2 = 1.69 gives 16 real nodes.
Polynomial kummerQuartic() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  const double mu2 = 1.69, lambda = (3.0 * mu2 - 1.0) / (3.0 - mu2), s = std::numbers::sqrt2;
  const Polynomial p = c(1.0) - z - s * x, q = c(1.0) - z + s * x;
  const Polynomial r = c(1.0) + z + s * y, t = c(1.0) + z - s * y;
  return (r2() - c(mu2)).pow(2) - lambda * (p * q * r * t);
}

// Togliatti's quintic: 31 nodes, the most a quintic can have (Togliatti 1940; Beauville
// 1980 for the bound), in the pentagonally symmetric form P - L Q^2 of Barth's
// construction, as usually quoted:
// 64 (x - w)(x^4 - 4x^3w - 10x^2y^2 - 4x^2w^2 + 16xw^3 - 20xy^2w + 5y^4 + 16w^4 - 20y^2w^2)
//   - 5 a (2z - a w)(4(x^2 + y^2 - z^2) + (1 + 3 sqrt5) w^2)^2,   a = sqrt(5 - sqrt5).
// The quintic factor is 1024 times the product of the five planes x cos t + y sin t = w,
// t = 2 pi k / 5 (the sides of a regular pentagon); where two of them meet, P vanishes
// to second order, and so f does where that line meets Q = 0: 20 nodes over the
// pentagon's vertices and the points of its star (tests/gallery_test.cpp). Solving
// grad f = 0 numerically (Newton from 3000 starts, sympy and mpmath) finds 6 more in the
// chart w = 1, (0, 0, -0.3717) and five at z = 1.2626: 26 within 4.8 of the origin; the
// other 5 lie at infinity.
Polynomial togliattiQuintic() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  const double s5 = std::sqrt(5.0), a = std::sqrt(5.0 - s5);
  const Polynomial pentagon = x.pow(4) - 4.0 * x.pow(3) - 10.0 * x * x * y * y - 4.0 * x * x +
                              16.0 * x - 20.0 * x * y * y + 5.0 * y.pow(4) + c(16.0) - 20.0 * y * y;
  const Polynomial q = 4.0 * (x * x + y * y - z * z) + c(1.0 + 3.0 * s5);
  return 64.0 * (x - c(1.0)) * pentagon - (5.0 * a) * (2.0 * z - c(a)) * q.pow(2);
}

// Barth's sextic (Barth, J. Alg. Geom. 5 (1996) 173-186), 65 nodes, icosahedral symmetry:
// 4 (phi^2 x^2 - y^2)(phi^2 y^2 - z^2)(phi^2 z^2 - x^2) - (1 + 2 phi)(x^2+y^2+z^2-w^2)^2 w^2.
Polynomial barthSextic() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  const double p2 = kPhi * kPhi;
  return 4.0 * (p2 * x * x - y * y) * (p2 * y * y - z * z) * (p2 * z * z - x * x) -
         (1.0 + 2.0 * kPhi) * (r2() - c(1.0)).pow(2);
}

// Labs' septic (O. Labs, "A septic with 99 real nodes", Rend. Sem. Mat. Univ. Padova 116
// (2006) 299-313; arXiv math.AG/0409348), 99 real nodes, the most known for degree 7 (the
// bound is 104), with the dihedral symmetry D7 about the z axis:
//   P - (z + a5 w) ((z + w)(x^2 + y^2) + a1 z^3 + a2 z^2 w + a3 z w^2 + a4 w^3)^2,
//   P = x (x^6 - 21 x^4 y^2 + 35 x^2 y^4 - 7 y^6)
//       + 7 z ((x^2 + y^2)^3 - 8 z^2 (x^2 + y^2)^2 + 16 z^4 (x^2 + y^2)) - 64 z^7,
// where P = Re (x + iy)^7 - r^7 T7(z / r) (r^2 = x^2 + y^2) is 64 times the product of the
// seven planes x cos t + y sin t = z, t = 2 pi k / 7 (the identity
// prod_k (cos s - cos(t + 2 pi k / n)) = 2^(1-n) (cos ns - cos nt); tests/gallery_test.cpp
// compares against the product), and with alpha the real root of 7 a^3 + 7 a + 1 = 0:
//   a1 = -12/7 alpha^2 - 384/49 alpha - 8/7,  a2 = -32/7 alpha^2 + 24/49 alpha - 4,
//   a3 = -4 alpha^2 + 24/49 alpha - 4,  a4 = -8/7 alpha^2 + 8/49 alpha - 8/7,
//   a5 = 49 alpha^2 - 7 alpha + 50.
// Checked before it went in: Newton on grad f = 0 from 20000 starts (numpy) finds 99
// points where f vanishes too, all in the chart w = 1: the 15 nodes of the plane section
// y = 0 (one on the axis, at (0, 0, -1)) and the orbits of the 14 others under D7 (Labs'
// count, 1 + 14 * 7). 71 of them lie within the clip radius 3.5; the last orbit is 15.8 out.
Polynomial labsSeptic() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  // alpha^3 + alpha + 1/7 = 0 has one real root (Cardano), refined by one Newton step on
  // 7 a^3 + 7 a + 1 (the two cube roots cancel in part).
  const double q = 1.0 / 7.0, d = std::sqrt(q * q / 4.0 + 1.0 / 27.0);
  double alpha = std::cbrt(-q / 2.0 + d) + std::cbrt(-q / 2.0 - d);
  alpha -= (7.0 * alpha * alpha * alpha + 7.0 * alpha + 1.0) / (21.0 * alpha * alpha + 7.0);
  const double a2 = alpha * alpha;
  const double a[6] = {0.0,
                       -12.0 / 7.0 * a2 - 384.0 / 49.0 * alpha - 8.0 / 7.0,
                       -32.0 / 7.0 * a2 + 24.0 / 49.0 * alpha - 4.0,
                       -4.0 * a2 + 24.0 / 49.0 * alpha - 4.0,
                       -8.0 / 7.0 * a2 + 8.0 / 49.0 * alpha - 8.0 / 7.0,
                       49.0 * a2 - 7.0 * alpha + 50.0};
  const Polynomial rho2 = x * x + y * y, z2 = z * z;
  const Polynomial p =
      x * (x.pow(6) - 21.0 * x.pow(4) * y * y + 35.0 * x * x * y.pow(4) - 7.0 * y.pow(6)) +
      7.0 * z * (rho2.pow(3) - 8.0 * z2 * rho2.pow(2) + 16.0 * z2.pow(2) * rho2) - 64.0 * z.pow(7);
  const Polynomial cubic = (z + c(1.0)) * rho2 + a[1] * z.pow(3) + a[2] * z2 + a[3] * z + c(a[4]);
  return p - (z + c(a[5])) * cubic.pow(2);
}

// Barth's decic (same paper), 345 nodes:
// 8 (x^2 - phi^4 y^2)(y^2 - phi^4 z^2)(z^2 - phi^4 x^2)(x^4+y^4+z^4 - 2x^2y^2 - 2y^2z^2 - 2z^2x^2)
//   + (3 + 5 phi)(x^2+y^2+z^2 - w^2)^2 (x^2+y^2+z^2 - (2 - phi) w^2)^2 w^2.
Polynomial barthDecic() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  const double p4 = std::pow(kPhi, 4);
  const Polynomial x2 = x * x, y2 = y * y, z2 = z * z;
  return 8.0 * (x2 - p4 * y2) * (y2 - p4 * z2) * (z2 - p4 * x2) *
             (x2 * x2 + y2 * y2 + z2 * z2 - 2.0 * (x2 * y2 + y2 * z2 + z2 * x2)) +
         (3.0 + 5.0 * kPhi) * (r2() - c(1.0)).pow(2) * (r2() - c(2.0 - kPhi)).pow(2);
}

// Taubin's heart (Taubin, "An accurate algorithm for rasterizing algebraic curves and
// surfaces", IEEE CG&A 1994): (x^2 + 9/4 y^2 + z^2 - 1)^3 - x^2 z^3 - 9/80 y^2 z^3.
Polynomial heart() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  return (x * x + 2.25 * y * y + z * z - c(1.0)).pow(3) - x * x * z.pow(3) -
         (9.0 / 80.0) * y * y * z.pow(3);
}

// Chebyshev polynomial T_n(v) by the recurrence T_{k+1} = 2 v T_k - T_{k-1}.
Polynomial chebyshev(int n, const Polynomial& v) {
  Polynomial previous = c(1.0), current = v;
  if (n == 0) return previous;
  for (int k = 1; k < n; ++k) {
    Polynomial next = 2.0 * (v * current) - previous;
    previous = std::move(current);
    current = std::move(next);
  }
  return current;
}

// Chmutov's surfaces T_n(x) + T_n(y) + T_n(z) + 1 = 0 (Chmutov 1992; the SURFER
// "record_chmutovoktic" is the n = 8 one divided by 128). Nodes where T_n' vanishes in
// all three variables with two of the T_n = -1 and one = +1.
template <int n>
Polynomial chmutov() {
  return chebyshev(n, X()) + chebyshev(n, Y()) + chebyshev(n, Z()) + c(1.0);
}

// Endrass' octic X+ (Endrass, "A projective surface of degree eight with 168 nodes",
// J. Alg. Geom. 6 (1997) 325-334), 168 real nodes:
// 64 (x^2-w^2)(y^2-w^2)((x+y)^2-2w^2)((x-y)^2-2w^2)
//   = [-4(1+sqrt2)(x^2+y^2)^2 + (8(2+sqrt2) z^2 + 2(2+7 sqrt2) w^2)(x^2+y^2)
//      - 16 z^4 + 8(1-2 sqrt2) z^2 w^2 - (1+12 sqrt2) w^4]^2.
Polynomial endrassOctic() {
  const Polynomial &x = X(), &y = Y(), &z = Z();
  const double s = std::numbers::sqrt2;
  const Polynomial rho2 = x * x + y * y, z2 = z * z;
  const Polynomial lhs = 64.0 * (x * x - c(1.0)) * (y * y - c(1.0)) * ((x + y).pow(2) - c(2.0)) *
                         ((x - y).pow(2) - c(2.0));
  const Polynomial quartic = -4.0 * (1.0 + s) * rho2.pow(2) +
                             (8.0 * (2.0 + s) * z2 + c(2.0 * (2.0 + 7.0 * s))) * rho2 -
                             16.0 * z2.pow(2) + 8.0 * (1.0 - 2.0 * s) * z2 - c(1.0 + 12.0 * s);
  return lhs - quartic.pow(2);
}

// The 120 vertices of the 600-cell (the unit quaternions of the binary icosahedral group
// 2I), one of each pair +-v: (+-1,0,0,0) and permutations, (+-1/2,+-1/2,+-1/2,+-1/2), and the
// even permutations of (+-phi/2, +-1/2, +-1/(2 phi), 0) (Coxeter, "Regular Polytopes", 8.7).
std::vector<std::array<double, 4>> sixHundredCellHalf() {
  std::vector<std::array<double, 4>> all;
  for (int i = 0; i < 4; ++i) {
    std::array<double, 4> v{0, 0, 0, 0};
    v[i] = 1.0;
    all.push_back(v);
  }
  for (int signs = 0; signs < 16; ++signs)
    all.push_back({signs & 1 ? -0.5 : 0.5, signs & 2 ? -0.5 : 0.5, signs & 4 ? -0.5 : 0.5,
                   signs & 8 ? -0.5 : 0.5});
  const double base[4] = {kPhi / 2, 0.5, 1.0 / (2.0 * kPhi), 0.0};
  std::array<int, 4> perm{0, 1, 2, 3};
  do {
    int inversions = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) inversions += perm[i] > perm[j];
    if (inversions % 2) continue;
    for (int signs = 0; signs < 8; ++signs) {
      std::array<double, 4> v{};
      for (int k = 0; k < 4; ++k) v[perm[k]] = (k < 3 && (signs >> k & 1)) ? -base[k] : base[k];
      all.push_back(v);
    }
  } while (std::next_permutation(perm.begin(), perm.end()));
  // Keep the representative whose first non-zero coordinate is positive.
  std::vector<std::array<double, 4>> half;
  for (const auto& v : all) {
    for (double c : v) {
      if (c == 0.0) continue;
      if (c > 0.0) half.push_back(v);
      break;
    }
  }
  return half;
}

// Sarti's dodecic (Sarti, "Pencils of symmetric surfaces in P3", J. Algebra 246 (2001)
// 429-452), 600 nodes. The bipolyhedral group (p -> a p b for a, b in 2I, p a quaternion
// (w, x, y, z)) has, besides Q^6 = |p|^12, one more invariant of degree 12,
//   S(p) = sum over the 60 vertex pairs +-c of the 600-cell of <c, p>^12
// (the 600-cell is a spherical 11-design, so S is not a multiple of Q^6). In the pencil
// S - lambda Q^6 a node at p needs grad S(p) parallel to p: p is a critical point of S on
// the unit sphere and lambda = S(p). The critical orbit of p* = (sqrt5, 1/phi, phi, 2)/(2 sqrt3)
// has 600 points in P^3 (found numerically; tests/gallery_test.cpp checks the nodes), so
// lambda = S(p*). Affine chart w = 1.
Polynomial sartiDodecic() {
  const auto cells = sixHundredCellHalf();
  const double s3 = std::sqrt(3.0);
  const std::array<double, 4> node{std::sqrt(5.0) / (2 * s3), 1.0 / (kPhi * 2 * s3),
                                   kPhi / (2 * s3), 2.0 / (2 * s3)};
  Polynomial s;
  double lambda = 0.0;
  for (const auto& v : cells) {
    s += (c(v[0]) + v[1] * X() + v[2] * Y() + v[3] * Z()).pow(12);
    lambda += std::pow(v[0] * node[0] + v[1] * node[1] + v[2] * node[2] + v[3] * node[3], 12);
  }
  return s - lambda * (r2() + c(1.0)).pow(6);
}

const std::array kGallery = {
    GallerySurface{"sphere", "unit sphere", 1.2, &sphere, "x^2 + y^2 + z^2 = 1"},
    GallerySurface{"ellipsoid", "ellipsoid with semi-axes 1, 0.75, 0.5", 1.2, &ellipsoid,
                   "x^2 + y^2/0.75^2 + z^2/0.5^2 = 1"},
    GallerySurface{"torus", "torus R = 1, r = 0.4 about the z axis", 1.6, &torus,
                   "(x^2 + y^2 + z^2 + 1 - 0.4^2)^2 = 4*(x^2 + y^2)"},
    GallerySurface{"clebsch-cubic", "Clebsch diagonal cubic, 27 real lines (Hunt's affine form)",
                   2.0, &clebschCubic},
    GallerySurface{"cayley-cubic", "Cayley's 4-nodal cubic", 2.5, &cayleyCubic,
                   "4*(x^3 + y^3 + z^3 + 1) = (x + y + z + 1)^3"},
    GallerySurface{"roman-surface", "Steiner's Roman surface", 0.75, &romanSurface,
                   "x^2*y^2 + y^2*z^2 + z^2*x^2 = x*y*z"},
    GallerySurface{"kummer-quartic", "Kummer quartic with 16 real nodes, mu^2 = 1.69 (SURFER form)",
                   2.5, &kummerQuartic},
    GallerySurface{"togliatti-quintic", "Togliatti's quintic, 31 nodes (26 affine; Barth's form)",
                   5.0, &togliattiQuintic},
    GallerySurface{"barth-sextic", "Barth's sextic, 65 nodes (Barth 1996)", 2.0, &barthSextic},
    GallerySurface{"labs-septic",
                   "Labs' septic, 99 real nodes (71 within the clip sphere; Labs 2006)", 3.5,
                   &labsSeptic},
    GallerySurface{"barth-decic", "Barth's decic, 345 nodes (Barth 1996)", 2.2, &barthDecic},
    GallerySurface{"heart", "Taubin's heart", 1.5, &heart,
                   "(x^2 + 9/4*y^2 + z^2 - 1)^3 = x^2*z^3 + 9/80*y^2*z^3"},
    GallerySurface{"chmutov-8", "Chmutov octic T8(x) + T8(y) + T8(z) + 1 = 0 (Chebyshev's T8)",
                   1.75, &chmutov<8>},
    GallerySurface{"chmutov-12",
                   "Chmutov dodecic T12(x) + T12(y) + T12(z) + 1 = 0 (Chebyshev's T12)", 1.75,
                   &chmutov<12>},
    GallerySurface{
        "chmutov-16",
        "Chmutov surface of degree 16, T16(x) + T16(y) + T16(z) + 1 = 0 (Chebyshev's T16)", 1.75,
        &chmutov<16>},
    GallerySurface{"endrass-octic", "Endrass' octic X+, 168 real nodes (Endrass 1997)", 2.5,
                   &endrassOctic},
    GallerySurface{"sarti-dodecic",
                   "Sarti's dodecic, 600 nodes, bipolyhedral symmetry (Sarti 2001)", 3.0,
                   &sartiDodecic},
};

}  // namespace

std::span<const GallerySurface> gallery() { return kGallery; }

namespace {

// A name as the gallery spells it: lower case, '-' between words.
std::string canonicalName(std::string_view name) {
  // Without the blanks around it (" torus" was an unknown name, "did you mean the gallery
  // surface 'torus'?": the audit of session 51).
  const auto blank = [](char ch) { return ch == ' ' || ch == '\t'; };
  while (!name.empty() && blank(name.front())) name.remove_prefix(1);
  while (!name.empty() && blank(name.back())) name.remove_suffix(1);
  std::string out(name);
  for (char& ch : out) {
    if (ch >= 'A' && ch <= 'Z') ch = static_cast<char>(ch - 'A' + 'a');
    if (ch == '_' || ch == ' ') ch = '-';
  }
  return out;
}

// The edit distance of a and b counting insertions, deletions, substitutions and swaps of
// neighbours ("tours" is one edit from "torus"): the optimal string alignment distance
// (Damerau's operations on Wagner and Fischer's table).
size_t editDistance(std::string_view a, std::string_view b) {
  const size_t w = b.size() + 1;
  std::vector<size_t> d((a.size() + 1) * w);
  for (size_t i = 0; i <= a.size(); ++i) d[i * w] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t best = std::min({d[(i - 1) * w + j] + 1, d[i * w + j - 1] + 1,
                              d[(i - 1) * w + j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        best = std::min(best, d[(i - 2) * w + j - 2] + 1);
      d[i * w + j] = best;
    }
  return d[a.size() * w + b.size()];
}

}  // namespace

const GallerySurface* findGallerySurface(std::string_view name) {
  const std::string wanted = canonicalName(name);
  for (const GallerySurface& s : kGallery)
    if (s.name == wanted) return &s;
  return nullptr;
}

std::vector<std::string_view> similarGallerySurfaces(std::string_view name) {
  const std::string wanted = canonicalName(name);
  std::vector<std::string_view> out;
  if (wanted.size() < 3) return out;  // "x", "a": an equation's name, not a surface's
  // Names one begins with the other, and of the names at most a third of their letters
  // away the closest ("chmutov8": chmutov-8, one edit, not chmutov-12, three).
  size_t closest = std::numeric_limits<size_t>::max();
  for (const GallerySurface& s : kGallery)
    if (const size_t d = editDistance(wanted, s.name); 3 * d <= s.name.size())
      closest = std::min(closest, d);
  for (const GallerySurface& s : kGallery) {
    const bool prefix = s.name.starts_with(wanted) || std::string_view(wanted).starts_with(s.name);
    if (prefix || editDistance(wanted, s.name) == closest) out.push_back(s.name);
  }
  return out;
}

std::string similarGallerySurfacesText(std::string_view name) {
  const std::vector<std::string_view> similar = similarGallerySurfaces(name);
  if (similar.empty()) return {};
  std::string out = similar.size() == 1 ? "the gallery surface " : "one of the gallery surfaces ";
  for (size_t i = 0; i < similar.size(); ++i)
    out += (i == 0 ? "'" : ", '") + std::string(similar[i]) + "'";
  return out;
}

std::string galleryNames() {
  std::string out;
  for (const GallerySurface& s : kGallery) {
    if (!out.empty()) out += ", ";
    out += s.name;
  }
  return out;
}

}  // namespace algray
