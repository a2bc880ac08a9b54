// The library's progress callback (PropagationOptions::progress) for a
// Python caller. The library computes without the GIL; every progress call
// takes it, lets Python handle pending signals (Ctrl-C cancels the run) and
// calls the caller's function, if any, with (finalised vertices, domain
// vertices, front distance). A false return cancels the run; an exception
// in the function cancels it and is raised again once the library returns.
#pragma once

#include <pybind11/pybind11.h>

#include <functional>
#include <optional>

#include "stvd/propagation/propagation.hpp"
#include "stvd/system/interrupter.hpp"

namespace stvd::python {

namespace py = pybind11;

class ProgressRelay {
 public:
  /// `callback` is None or a callable; it is borrowed (the caller's
  /// argument outlives the run), so the hook never touches a reference
  /// count without the GIL.
  explicit ProgressRelay(py::handle callback) : callback_(callback) {}
  ProgressRelay(const ProgressRelay&) = delete;
  ProgressRelay& operator=(const ProgressRelay&) = delete;

  /// The hook to put into the options; valid while this relay lives. May
  /// be called from several threads at once.
  std::function<bool(const PropagationProgress&)> hook() {
    return [this](const PropagationProgress& p) { return relay(p); };
  }

  /// An Interrupter for the loops of an operation that are not a
  /// propagation (region connectivity's own, its paths): every report
  /// takes the GIL and lets Python handle pending signals, so that Ctrl-C
  /// (or an earlier exception of the callback) stops them too; the callback
  /// itself is not called (its arguments are a propagation's). Valid while
  /// this relay lives. May be called from several threads at once.
  Interrupter* interrupter() { return &signals_; }

  /// With the GIL held, after the library returned: raises the exception
  /// that cancelled the run, if any.
  void rethrowIfFailed() {
    if (error_) {
      py::error_already_set error = std::move(*error_);
      error_.reset();
      throw error;
    }
  }

 private:
  bool relay(const PropagationProgress& p) {
    py::gil_scoped_acquire gil;
    if (error_) return false;
    if (PyErr_CheckSignals() != 0) {
      error_.emplace();
      return false;
    }
    if (callback_.is_none()) return true;
    try {
      const py::object answer = callback_(p.finalizedVertices, p.domainVertices, p.frontDistance);
      if (answer.is_none()) return true;
      const int truth = PyObject_IsTrue(answer.ptr());
      if (truth < 0) error_.emplace();  // an answer without a truth value
      return truth == 1;
    } catch (py::error_already_set& e) {
      error_.emplace(std::move(e));
      return false;
    }
  }

  bool signalled() {
    py::gil_scoped_acquire gil;
    if (error_) return true;
    if (PyErr_CheckSignals() != 0) {
      error_.emplace();
      return true;
    }
    return false;
  }

  class SignalInterrupter final : public Interrupter {
   public:
    explicit SignalInterrupter(ProgressRelay& relay) : relay_(relay) {}
    bool wasInterrupted(int) override { return relay_.signalled(); }

   private:
    ProgressRelay& relay_;
  };

  py::handle callback_;
  std::optional<py::error_already_set> error_;  // touched with the GIL held only
  SignalInterrupter signals_{*this};
};

}  // namespace stvd::python
