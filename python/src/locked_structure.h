// What the three Python structure wrappers (_Accelerator, _DoubleAccelerator, _InstancedAccelerator) share: one
// structure behind one reader/writer lock, taken the same way by every accessor, and one batch body.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <span>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "arrays.h"
#include "rayaccel/core/ray_d.h"

namespace rayaccel::python {

/// Throws ValueError naming the first void double ray (double_bindings.cpp); trace(0, n) after, as one call: the
/// double batches are not split into checked blocks.
void trace_checked(std::span<const RayD> rays, bool check, const std::function<void(std::size_t, std::size_t)>& trace);

/// The rays of an (N, 8) array in place: float32 as Ray (.rays), float64 as RayD (.rays64).
template <class RayT>
struct BatchRays {
  using Real = decltype(RayT::t_min);
  static_assert(sizeof(RayT) == 8 * sizeof(Real));
  explicit BatchRays(const py::handle& object)
      : array(real_rows<Real>(object, 8, "rays")),
        rays(reinterpret_cast<const RayT*>(array.data()), static_cast<std::size_t>(array.shape(0))) {}
  RealRows<Real> array;  // keeps the numpy buffer (or its converted copy) alive
  std::span<const RayT> rays;
};

/// One record per ray as an (N, sizeof(Record)) uint8 array: a new one, or `out` when it is not None (ValueError
/// unless it is such an array, writable and C-contiguous).
template <class Record>
std::pair<py::array_t<std::uint8_t>, std::span<Record>> record_array(std::size_t n, const py::object& out) {
  constexpr auto width = static_cast<py::ssize_t>(sizeof(Record));
  py::array_t<std::uint8_t> records;
  if (out.is_none()) {
    records = py::array_t<std::uint8_t>({static_cast<py::ssize_t>(n), width});
  } else {
    const auto given = py::reinterpret_borrow<py::array>(out);
    if (!py::isinstance<py::array_t<std::uint8_t>>(out) || given.ndim() != 2 || given.shape(1) != width ||
        static_cast<std::size_t>(given.shape(0)) != n || !(given.flags() & py::array::c_style) ||
        !given.writeable()) {
      throw ValueError("out must hold one writable, C-contiguous hit record per ray (" + std::to_string(n) + " rays)");
    }
    records = py::reinterpret_borrow<py::array_t<std::uint8_t>>(out);
  }
  return {records, {reinterpret_cast<Record*>(records.mutable_data()), n}};
}

/// (N,) bool answers and their bytes.
inline std::pair<py::array_t<bool>, std::span<std::uint8_t>> answer_array(std::size_t n) {
  static_assert(sizeof(bool) == 1);
  py::array_t<bool> answers(static_cast<py::ssize_t>(n));
  return {answers, {reinterpret_cast<std::uint8_t*>(answers.mutable_data()), n}};
}

/// A `Structure` built over a `SceneT` that it keeps alive. Batches and accessors take the lock shared, builds and
/// changes exclusively, so no change runs under another thread's batch (both run without the GIL). Accessors keep
/// the GIL: they wait for a change running in another thread (which needs no GIL until it ends), never the other way
/// round. Results are copies: a reference into a structure that load() replaces would dangle.
/// `Derived` provides `static std::string not_built(const Structure&)` (the error for queries before build()) and
/// may hide `mutex()` to share another object's lock (the instanced scene's).
template <class Derived, class Structure, class SceneT>
class LockedStructure {
 public:
  bool built() const {
    return read([&](const Structure&) { return scene_ != nullptr; });
  }
  std::shared_ptr<SceneT> scene() const {
    return read([&](const Structure&) { return scene_; });
  }
  std::string spec() const {
    return read([](const Structure& s) { return std::string(s.spec()); });
  }
  double build_ms() const {
    return read([&](const Structure&) { return build_ms_; });
  }
  std::size_t memory_bytes() const {
    return read_built([](const Structure& s) { return s.memory_bytes(); });
  }
  std::vector<std::string> validate() const {
    return query([](const Structure& s, const SceneT&) { return s.validate(); });
  }

 protected:
  explicit LockedStructure(std::unique_ptr<Structure> structure) : structure_(std::move(structure)) {}

  std::shared_mutex& mutex() const { return mutex_; }

  /// f(structure), built or not, under the shared lock with the GIL held.
  template <class F>
  auto read(F&& f) const {
    std::shared_lock lock(derived().mutex());
    return f(*structure_);
  }
  /// f(structure) once built (ValueError otherwise), under the shared lock with the GIL held.
  template <class F>
  auto read_built(F&& f) const {
    std::shared_lock lock(derived().mutex());
    return f(require_built());
  }
  /// f(structure, scene) once built, under the shared lock without the GIL: every query.
  template <class F>
  auto query(F&& f) const {
    std::shared_mutex& mutex = derived().mutex();
    py::gil_scoped_release release;
    std::shared_lock lock(mutex);
    return f(require_built(), *scene_);
  }
  /// The batch body of every wrapper: require(structure), then body(structure, begin, end) over blocks of `rays`
  /// (each block checked first when `check`, see trace_checked), under the shared lock without the GIL.
  template <class RayT, class Body, class Require = void (*)(const Structure&)>
  void trace(std::span<const RayT> rays, bool check, Body&& body, Require&& require = [](const Structure&) {}) const {
    query([&](const Structure& s, const SceneT&) {
      require(s);
      trace_checked(rays, check, [&](std::size_t begin, std::size_t end) { body(s, begin, end); });
    });
  }
  /// f(structure_, scene_) under the exclusive lock without the GIL; `timed` records its time as build_ms.
  template <class F>
  auto change(bool timed, F&& f) {
    std::shared_mutex& mutex = derived().mutex();
    py::gil_scoped_release release;
    std::unique_lock lock(mutex);
    const auto start = std::chrono::steady_clock::now();
    if constexpr (std::is_void_v<decltype(f(structure_, scene_))>) {
      f(structure_, scene_);
      if (timed) build_ms_ = elapsed_ms(start);
    } else {
      auto result = f(structure_, scene_);
      if (timed) build_ms_ = elapsed_ms(start);
      return result;
    }
  }
  /// Builds over `scene` (kept alive), timed; a failed build leaves the structure unbuilt.
  void build_over(std::shared_ptr<SceneT> scene) {
    change(true, [&](std::unique_ptr<Structure>& s, std::shared_ptr<SceneT>& current) {
      current.reset();
      s->build(*scene);
      current = std::move(scene);
    });
  }
  /// The structure once built (ValueError otherwise); call under the lock.
  const Structure& require_built() const {
    if (!scene_) throw ValueError(Derived::not_built(*structure_));
    return *structure_;
  }

 private:
  const Derived& derived() const { return static_cast<const Derived&>(*this); }
  static double elapsed_ms(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }

  std::unique_ptr<Structure> structure_;
  std::shared_ptr<SceneT> scene_;
  double build_ms_ = 0.0;
  mutable std::shared_mutex mutex_;
};

}  // namespace rayaccel::python
