#pragma once
// The direct restriction over a HornerForm's box as it was before the unrolled kernels of
// plugin/core/taylor_box.cpp (commit 717a286): run-time loops only, one Horner step at a
// time. The library's version must return the same bits as this one (signed zeros too);
// it is kept verbatim so that the unrolled code has a fixed target.
//
// Note: this path and restrictToRay(const Polynomial&, ...) agree in value, not always in
// the sign of a zero coefficient (the Polynomial path adds the zeros of its dense arrays
// above F's degree, turning a -0 into +0; the box path never touches them).
#include <algorithm>
#include <cmath>

#include "algray/taylor.h"

namespace algray::test {

namespace box_reference {

typedef double Pair __attribute__((vector_size(16)));

inline void mulLinear(Pair* q, int deg, Pair p, Pair d) {
  q[deg + 1] = d * q[deg];
  for (int r = deg; r >= 1; --r) q[r] = p * q[r] + d * q[r - 1];
  q[0] = p * q[0];
}

inline void hornerStep(Pair* h, int& degH, double c, Pair p, Pair d) {
  if (degH < 0 && c == 0.0) return;
  const Pair term = {c, std::abs(c)};
  if (degH < 0) {
    h[0] = term;
  } else {
    mulLinear(h, degH, p, d);
    h[0] += term;
  }
  ++degH;
}

inline void boxHorner(const HornerForm& f, const glm::dvec3& p, const glm::dvec3& d, double* g,
                      double* mag) {
  const Pair px = {p.x, std::abs(p.x)}, py = {p.y, std::abs(p.y)}, pz = {p.z, std::abs(p.z)};
  const Pair dx = {d.x, std::abs(d.x)}, dy = {d.y, std::abs(d.y)}, dz = {d.z, std::abs(d.z)};
  Pair gx[kMaxDegree + 2], fy[kMaxDegree + 2], fz[kMaxDegree + 2];
  int degG = -1;
  const HornerForm::Slot* s = f.slots().data();
  const std::uint8_t* len = f.rowLengths().data();
  auto accumulate = [](Pair* acc, int da, const Pair* q, int dq) {
    for (int r = da + 1; r <= dq; ++r) acc[r] = Pair{0.0, 0.0};
    for (int r = 0; r <= dq; ++r) acc[r] += q[r];
    return std::max(da, dq);
  };
  for (const std::uint8_t rows : f.blockRows()) {
    if (degG >= 0) mulLinear(gx, degG++, px, dx);
    int degF = -1;
    for (int r = 0; r < rows; ++r) {
      if (degF >= 0) mulLinear(fy, degF++, py, dy);
      int degH = -1;
      for (const HornerForm::Slot* end = s + *len++; s != end; ++s)
        hornerStep(fz, degH, s->c, pz, dz);
      if (degH >= 0) degF = accumulate(fy, degF, fz, degH);
    }
    if (degF >= 0) degG = accumulate(gx, degG, fy, degF);
  }
  const int m = f.degree();
  for (int r = 0; r <= m; ++r) {
    g[r] = r <= degG ? gx[r][0] : 0.0;
    mag[r] = r <= degG ? gx[r][1] : 0.0;
  }
}

}  // namespace box_reference

inline RayPolynomial restrictToRayReference(const HornerForm& f, const glm::dvec3& o,
                                            const glm::dvec3& d, double tShift) {
  RayPolynomial g;
  g.tShift = tShift;
  const int m = f.degree();
  if (m < 0) return g;
  const glm::dvec3 p = tShift == 0.0 ? o : o + tShift * d;
  double mag[kMaxDegree + 1];
  box_reference::boxHorner(f, p, d, g.coeff.data(), mag);
  const double factor = gamma(3 * m + 3) * (1.0 + gamma(3 * m + 3));
  // The underflow floor is no part of the kernels: the library's own (taylor.h).
  const auto floor = restrictionUnderflowFloor(f, p, d);
  g.degree = m;
  for (int i = 0; i <= m; ++i) {
    const double e = factor * mag[i] + floor[i];
    g.error[i] = e >= 0.0 ? e : HUGE_VAL;
  }
  return g;
}

}  // namespace algray::test
