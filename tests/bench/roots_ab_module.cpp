// The first-root solver of this build behind one C entry point, as a loadable module for
// roots_ab.cpp, which loads two builds of it (this tree's and another commit's) into one
// process and times them pass by pass. Only the entry point is exported (the core's own
// symbols stay local: CMakeLists.txt), so two modules never resolve to each other.
#include "algray/roots.h"

#include <cstddef>

extern "C" [[gnu::visibility("default")]] bool algrayAbFirstRoot(const double* c, std::size_t count,
                                                                 double lo, double hi, int method,
                                                                 double* root) noexcept {
  try {
    algray::RootOptions options;
    options.method = static_cast<algray::RootMethod>(method);
    return algray::solveFirstRoot(std::span<const double>(c, count), {}, lo, hi, *root, options);
  } catch (...) {  // (sizes beyond kMaxDegree: the driver asks for none)
    return false;
  }
}
