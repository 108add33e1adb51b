#pragma once
// Real roots of a univariate polynomial g(s) = sum c[i] s^i in an open interval: the
// first root (closest hit), whether any root exists (occlusion), and all roots in order.
// Independent of Embree. See plugin/core/roots*.cpp for the methods and their
// references (closed forms for degree <= 4, Yuksel's HPG 2022 critical-point splitting
// above, a Sturm-sequence and a Bernstein subdivision solver kept for comparison).
#include "algray/polynomial.h"  // kMaxDegree, Error

#include <optional>
#include <span>

namespace algray {

enum class RootMethod {
  Auto,        // the measured winner per degree (closed forms <= 4, else Yuksel)
  ClosedForm,  // degrees 1..4 only; others fall back to Auto
  Yuksel,      // recursive critical points + safeguarded Newton
  Sturm,       // Sturm sequence isolation + bisection/Newton (POV-Ray style)
  Bernstein,   // Bernstein/Descartes subdivision
};

struct RootOptions {
  RootMethod method = RootMethod::Auto;
  // Relative tolerance on a root, relative to the interval length; 0 means full
  // precision (iterate until the root is bracketed to adjacent doubles or Newton stalls).
  double relTolerance = 0.0;
};

// The interval is open: roots equal to lo or hi are not reported. c has degree+1
// entries (c[degree] may be rounding noise: leading coefficients negligible against the
// others, by the rule documented in roots.cpp, are dropped). err, if not empty, has the
// same size and bounds the absolute error of each c[i]; it decides even-multiplicity
// (tangent) roots: where |g| at a local extremum is within the error bound, the
// extremum counts as a root. Non-finite input gives "no root", never a hang.
std::optional<double> firstRoot(std::span<const double> c, std::span<const double> err, double lo,
                                double hi, const RootOptions& options = {});
bool hasRoot(std::span<const double> c, std::span<const double> err, double lo, double hi,
             const RootOptions& options = {});
// Writes the roots in increasing order (each multiple root once) into out and returns how
// many there are (at most out.size()).
int allRoots(std::span<const double> c, std::span<const double> err, double lo, double hi,
             std::span<double> out, const RootOptions& options = {});

// Float variants, kept for the speed/error comparison.
std::optional<float> firstRoot(std::span<const float> c, std::span<const float> err, float lo,
                               float hi, const RootOptions& options = {});
bool hasRoot(std::span<const float> c, std::span<const float> err, float lo, float hi,
             const RootOptions& options = {});

}  // namespace algray
