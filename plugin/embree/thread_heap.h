#pragma once
// A per-thread object on the heap, freed at thread exit by a POSIX thread key.
//
// Why not a `thread_local T`: for a T with a destructor (vectors) C++ registers that
// destructor on a thread's first use through __cxa_thread_atexit, which takes the dynamic
// loader's lock, so the first ray of every thread waited for any dlopen running in the
// host at that moment (measured: algray-render's render thread stood still for the whole
// 0.17 s load of OpenImageIO on its second thread; the render loop of a torus took 0.29 s
// instead of 0.11 s). The key frees the object without that lock; the thread_local is only
// a pointer (trivially destructible: nothing registered), cleared with the object, since a
// host's own key destructor may trace rays after ours at thread exit (it read the freed
// origin cache through the pointer until session 45).
#include <pthread.h>

#include <atomic>
#include <memory>
#include <new>

namespace algray {

template <class T>
class ThreadHeap {
 public:
  // The calling thread's object, created (value-initialised) on first use; throws
  // std::bad_alloc where it cannot be made (the Embree bridge counts that as a miss).
  static T& get() {
    if (object_) return *object_;
    // After the library's statics are gone (a host tracing from a static destructor on a
    // new thread, where the deleted key threw and the ray missed), the object is made
    // without a key and lives as long as the process, on a list that keeps it reachable
    // (LeakSanitizer reported it when only the exited thread had held it).
    if (keyDeleted_.load(std::memory_order_acquire)) {
      auto* orphan = new Orphan();
      orphan->next = orphans_.load(std::memory_order_relaxed);
      while (!orphans_.compare_exchange_weak(orphan->next, orphan, std::memory_order_release,
                                             std::memory_order_relaxed)) {
      }
      object_ = &orphan->object;
      return *object_;
    }
    static const Key key;
    auto owned = std::make_unique<T>();
    if (pthread_setspecific(key.key, owned.get()) != 0) throw std::bad_alloc();
    object_ = owned.release();
    return *object_;
  }

 private:
  // Deleted with the library's statics: a host that dlcloses a plugin linking algray
  // while its threads live on crashed at their exit, in a destructor no longer mapped
  // (and each load leaked a key). The objects of threads alive then are not freed.
  struct Key {
    pthread_key_t key{};
    Key() {
      if (pthread_key_create(&key, &release) != 0) throw std::bad_alloc();
    }
    ~Key() {
      keyDeleted_.store(true, std::memory_order_release);
      pthread_key_delete(key);
    }
    Key(const Key&) = delete;
    Key& operator=(const Key&) = delete;
  };
  static void release(void* p) {
    if (object_ == p) object_ = nullptr;
    delete static_cast<T*>(p);
  }
  static constinit inline thread_local T* object_ = nullptr;
  static constinit inline std::atomic<bool> keyDeleted_{false};  // trivially destructible
  struct Orphan {
    T object{};
    Orphan* next = nullptr;
  };
  static constinit inline std::atomic<Orphan*> orphans_{nullptr};
};

}  // namespace algray
