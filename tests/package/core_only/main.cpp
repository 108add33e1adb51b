// algray-core-only: the first root of x^3 - 2 on (0, 4] from a parsed equation, against the
// closed form cbrt(2). Exit code 0 when they agree to a few ulps.
#include <algray/parser.h>
#include <algray/roots.h>

#include <cmath>
#include <cstdio>
#include <vector>

int main() {
  const algray::Polynomial p = algray::parsePolynomial("x^3 - a", {.parameters = {{"a", 2.0}}});
  std::vector<double> c;
  for (int i = 0; i <= p.degree(); ++i) c.push_back(p.coeff(i, 0, 0));
  const std::optional<double> root = algray::firstRoot(c, {}, 0.0, 4.0);
  const double exact = std::cbrt(2.0);
  std::printf("first root of x^3 - 2 on (0, 4]: %.17g (cbrt(2) = %.17g)\n", root.value_or(-1),
              exact);
  return root && std::abs(*root - exact) <= 4e-16 * exact ? 0 : 1;
}
