// penumbra's C++ API: header-only over the C API (one exported ABI, so the two cannot drift apart). Its names live in
// the inline namespace penumbra::v0 (the SOVERSION): users write penumbra::Context, and no symbol of these inline
// classes can collide with the library's own, even when libpenumbra.a is linked in statically. This file: the
// exception every failing call throws, and the reference-counted handle the classes hold.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

#include "penumbra/status.h"

/// @file
/// Errors, handles and the version for the C++ API.

namespace penumbra {
inline namespace v0 {

/// A failed call: the C API's status, its message (the same text as pn_last_error_message()) and, for
/// Status PN_ERROR_OPENCL, the OpenCL error code.
class Error : public std::runtime_error {
 public:
  /// A failure with `status`, its `message` and, for PN_ERROR_OPENCL, the OpenCL error code.
  Error(pn_status status, const std::string& message, cl_int clError)
      : std::runtime_error(message), status_(status), clError_(clError) {}
  /// The C API's status code.
  pn_status status() const noexcept { return status_; }
  /// The OpenCL error code (CL_SUCCESS unless status() is PN_ERROR_OPENCL).
  cl_int clError() const noexcept { return clError_; }

 private:
  pn_status status_;
  cl_int clError_;
};

/// The library's version, "MAJOR.MINOR.PATCH" (pn_version()).
inline std::string version() { return pn_version(); }

namespace detail {

// Throws Error for a failed status, with this thread's message.
inline void check(pn_status status) {
  if (status != PN_SUCCESS) throw Error(status, pn_last_error_message(), pn_last_cl_error());
}

// One reference to a C handle: copies retain, destruction releases.
template <class T, pn_status (*Retain)(T*), pn_status (*Release)(T*)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(T* owned) noexcept : handle_(owned) {}  // takes over the reference `owned` came with
  Handle(const Handle& other) : handle_(other.handle_) {
    if (handle_ != nullptr) check(Retain(handle_));
  }
  Handle(Handle&& other) noexcept : handle_(std::exchange(other.handle_, nullptr)) {}
  Handle& operator=(Handle other) noexcept {
    std::swap(handle_, other.handle_);
    return *this;
  }
  ~Handle() {
    if (handle_ != nullptr) Release(handle_);
  }
  T* get() const noexcept { return handle_; }

 private:
  T* handle_ = nullptr;
};

}  // namespace detail
}  // namespace v0
}  // namespace penumbra
