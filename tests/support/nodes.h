#pragma once
// Singular points of f (f = 0 and grad f = 0) inside a ball, found independently of the
// library's intersector: Newton's method on grad f = 0 (the Hessian as Jacobian) from a
// grid of starts, kept where it converges inside the ball with f = 0 within 1000 times
// its evaluation bound, duplicates (closer than 1e-7) merged. Nodes are non-degenerate
// critical points (non-singular Hessian), so Newton converges quadratically to each from
// a neighbourhood, and a grid fine against their spacing reaches all of them; tests
// assert the count the literature gives, so a missed node fails the test.
#include "algray/polynomial.h"

#include <glm/glm.hpp>

#include <cmath>
#include <vector>

namespace algray::test {

inline std::vector<glm::dvec3> findNodes(const Polynomial& f, const glm::dvec3& centre,
                                         double radius, int grid = 16) {
  Polynomial g[3], h[3][3];
  for (int i = 0; i < 3; ++i) g[i] = f.derivative(i);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) h[i][j] = g[i].derivative(j);
  std::vector<glm::dvec3> nodes;
  for (int a = 0; a < grid; ++a)
    for (int b = 0; b < grid; ++b)
      for (int c = 0; c < grid; ++c) {
        glm::dvec3 x = centre + radius * ((2.0 * glm::dvec3(a, b, c) + 1.0) / double(grid) - 1.0);
        bool converged = false;
        for (int it = 0; it < 60 && !converged; ++it) {
          const glm::dvec3 gradient(g[0].evaluate(x), g[1].evaluate(x), g[2].evaluate(x));
          glm::dmat3 hessian;
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) hessian[j][i] = h[i][j].evaluate(x);
          if (!(std::abs(glm::determinant(hessian)) > 0.0)) break;
          const glm::dvec3 step = glm::inverse(hessian) * gradient;
          x -= step;
          if (!(glm::length(x - centre) < 3.0 * radius)) break;
          converged = glm::length(step) < 1e-14 * (1.0 + glm::length(x));
        }
        if (!converged || glm::length(x - centre) > radius) continue;
        const Polynomial::Evaluation e = f.evaluateWithBound(x);
        if (std::abs(e.value) > 1e3 * e.valueError) continue;  // a critical point off f = 0
        bool known = false;
        for (const glm::dvec3& y : nodes) known = known || glm::length(y - x) < 1e-7;
        if (!known) nodes.push_back(x);
      }
  return nodes;
}

}  // namespace algray::test
