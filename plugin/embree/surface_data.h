#pragma once
// The adapter's private state of one surface geometry, and the Embree-free kernel that
// walks the roots of one ray through one cell. Shared by surface_geometry.cpp (set-up),
// surface_intersect.cpp (the kernel) and embree_bridge.cpp (the callback ABI).
#include "algray/embree.h"

#include <atomic>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

namespace algray {

// One Embree primitive: an object-space box (a cell, or the box of the whole clip region)
// and its padded world-space bounds.
struct SurfaceCell {
  glm::dvec3 lo{0.0}, hi{0.0};
  RTCBounds bounds{};
};

// A degree-2 surface as f(x) = x^T A x + b . x + c (A symmetric), for the quadric path of
// surface_intersect.cpp: restriction, self-root test and normal in closed form.
struct QuadricForm {
  glm::dmat3 a{0.0};
  glm::dvec3 b{0.0};
  double c = 0;
  glm::dmat3 absA{0.0};  // |A|, |b| entrywise, for the error bounds
  glm::dvec3 absB{0.0};
  static QuadricForm fromPolynomial(const Polynomial& f);
};

struct SurfaceData {
  SurfaceDesc desc;
  std::optional<QuadricForm> quadric;  // set when desc.polynomial has degree 2 exactly
  // desc.transform = [a | b]: world p = a x + b; x = aInv (p - b); normals by aInvT.
  glm::dmat3 a{1.0}, aInv{1.0}, aInvT{1.0};
  glm::dvec3 b{0.0};
  bool identity = true;
  // Centre and radius of a ball holding the clip region (object space): the frame for
  // re-centring and the scale every relative tolerance of the adapter refers to.
  glm::dvec3 centre{0.0};
  double radius = 1.0;
  std::vector<SurfaceCell> cells;
  // The cells' grid (they are one level of a regular subdivision of the box around the
  // clip region): box corner, size and cells per axis, and the cell of each grid key.
  // Empty when there is one cell or the cells are not a regular grid.
  glm::dvec3 gridLo{0.0}, gridSize{1.0}, gridN{1.0};
  std::unordered_map<std::uint64_t, unsigned> cellOfKey;
  RTCGeometry geometry = nullptr;
  std::uint64_t id = 0;  // unique per process: keys the per-thread origin cache
  mutable std::atomic<unsigned long long> errors{0};
};

// A ray in the surface's object space.
struct KernelRay {
  glm::dvec3 org{0.0};
  glm::dvec3 dir{0.0};
  double tnear = 0;
  double tfar = 0;
  // Relative uncertainty of the origin coordinates (unit roundoff of the precision the
  // host stored them in) and an absolute bound given by the host (RayD::orgError).
  double orgRoundoff = kUnitRoundoff;
  double orgError = 0;
  // The float ray Embree traverses with (geometry space), when it differs from this one
  // (the double channel): a root is owned by a cell that Embree can reach.
  bool hasTraversalRay = false;
  glm::dvec3 travOrg{0.0}, travDir{0.0};
};

// A candidate root handed to the acceptance callback (the host filter).
struct KernelHit {
  double t = 0;
  glm::dvec3 point{0.0};     // object space
  glm::dvec3 gradient{0.0};  // object space; zero for occlusion queries
};

// Returns true to accept the candidate (stop), false to ask for the next root.
using AcceptFn = bool (*)(void* user, const KernelHit& hit);

// Walks the roots of f(o + t d) in increasing t inside cell `cell`, restricted to the
// open interval (tnear, tfar), and offers each to accept(). Returns whether one was
// accepted. Never throws for non-finite input (no roots); may throw algray::Error or
// std::bad_alloc, which the bridge catches.
bool walkRoots(const SurfaceData& data, unsigned cell, const KernelRay& ray, bool occlusion,
               AcceptFn accept, void* user);

// u, v of a hit point as documented in algray/embree.h.
void surfaceUV(const SurfaceData& data, const glm::dvec3& point, double& u, double& v);

}  // namespace algray
