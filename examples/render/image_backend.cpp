// Loading libalgray_render_oiio.so on a background thread: see image_backend.h for why.
#include "image_backend.h"

#include <dlfcn.h>

#include <cstdlib>

#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace algray::render {

namespace {

constexpr const char* kModuleName = "libalgray_render_oiio.so";

// Next to the program (build tree), in the installed library directory, then where the
// build tree put it (test programs live in another directory of the build tree).
std::vector<std::string> candidatePaths() {
  std::vector<std::string> paths;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    paths.push_back((exe.parent_path() / kModuleName).string());
    paths.push_back(
        (exe.parent_path().parent_path() / ALGRAY_RENDER_INSTALL_LIBDIR / "algray" / kModuleName)
            .string());
  }
  paths.push_back(ALGRAY_RENDER_OIIO_MODULE);
  return paths;
}

class Loader {
 public:
  ~Loader() {
    if (thread_.joinable()) thread_.join();
  }

  void start(std::function<void(const ImageBackend*)> whenLoaded) {
    std::call_once(started_, [this, &whenLoaded] {
      whenLoaded_ = std::move(whenLoaded);
      // OpenBLAS (OIIO -> OpenCV -> ... -> OpenBLAS) starts one busy-waiting worker per
      // core when it loads; image I/O never calls BLAS. Set before the load, on the
      // calling thread; a user's own setting wins.
      setenv("OPENBLAS_NUM_THREADS", "1", 0);
      thread_ = std::thread([this] {
        load();
        if (whenLoaded_) whenLoaded_(backend_);
      });
    });
  }

  const ImageBackend& get() {
    start({});
    std::call_once(joined_, [this] { thread_.join(); });
    if (!backend_)
      throw std::runtime_error("cannot load the image module (OpenImageIO): " + error_);
    return *backend_;
  }

 private:
  void load() {
    for (const std::string& path : candidatePaths()) {
      // RTLD_LOCAL: OIIO's symbols stay out of the program's scope. Never closed: OIIO
      // keeps global state until exit.
      void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
      if (!handle) {
        const char* e = dlerror();
        error_ += "\n  " + path + ": " + (e ? e : "not loadable");
        continue;
      }
      using Entry = const ImageBackend* (*)();
      auto entry = reinterpret_cast<Entry>(dlsym(handle, "algrayRenderImageBackend"));
      if (entry && (backend_ = entry())) return;
      error_ += "\n  " + path + ": no algrayRenderImageBackend";
    }
  }

  std::once_flag started_, joined_;
  std::function<void(const ImageBackend*)> whenLoaded_;
  std::thread thread_;
  const ImageBackend* backend_ = nullptr;  // written by the thread, read after join
  std::string error_;
};

Loader& loader() {
  static Loader instance;
  return instance;
}

}  // namespace

void startLoadingImageBackend(std::function<void(const ImageBackend*)> whenLoaded) {
  loader().start(std::move(whenLoaded));
}

const ImageBackend& imageBackend() { return loader().get(); }

}  // namespace algray::render
