// A shared library for tests/embree_threads_test.cpp: its constructor runs inside the
// test's dlopen, i.e. while the dynamic loader holds its lock (glibc runs ELF constructors
// under dl_load_lock), and calls the test's hook there, found by name in the executable.
#include <dlfcn.h>

namespace {

struct Probe {
  Probe() {
    using Hook = void (*)();
    if (auto hook = reinterpret_cast<Hook>(dlsym(RTLD_DEFAULT, "algrayTestInsideDlopen"))) hook();
  }
} probe;

}  // namespace
