// The C boundary: every API function runs its body through guard(), which turns any exception into a status and this
// thread's message, so none crosses into C; retainHandle / releaseHandle count the handles' references.
#pragma once

#include <atomic>
#include <stdexcept>
#include <string>

#include "penumbra/status.h"

namespace penumbra::api {

// Records a failure for pn_last_error_message() / pn_last_cl_error() and returns `status`. Never throws.
pn_status fail(pn_status status, const char* message, cl_int clError = CL_SUCCESS) noexcept;

// The status and message of the exception in flight (call inside a catch block).
pn_status failCurrentException() noexcept;

// Runs body(); PN_SUCCESS, or the status of the exception it threw.
template <class Body>
pn_status guard(Body&& body) noexcept {
  try {
    body();
    return PN_SUCCESS;
  } catch (...) {
    return failCurrentException();
  }
}

// Throws std::invalid_argument "FUNCTION: NAME is NULL" for a null pointer argument.
template <class T>
T* require(T* pointer, const char* function, const char* name) {
  if (pointer == nullptr) throw std::invalid_argument(std::string(function) + ": " + name + " is NULL");
  return pointer;
}

// A settings struct the caller filled after its *_init function: its `size` (sizeof the struct as the caller compiled
// it) must hold every field of the struct's first version, `firstSize` bytes; fields a later version adds lie beyond
// and are read only when `size` holds them. Throws std::invalid_argument naming the struct and its init function.
template <class Struct>
const Struct& requireSized(const Struct* settings, size_t firstSize, const char* function, const char* name,
                           const char* init) {
  require(settings, function, name);
  if (settings->size < firstSize)
    throw std::invalid_argument(std::string(function) + ": " + name + "->size " + std::to_string(settings->size) +
                                " is smaller than its first version's " + std::to_string(firstSize) + " bytes (call " +
                                init + " first)");
  return *settings;
}

template <class Handle>
pn_status retainHandle(Handle* handle, const char* function) noexcept {
  if (handle == nullptr) return fail(PN_ERROR_INVALID_ARGUMENT, (std::string(function) + ": NULL handle").c_str());
  handle->references.fetch_add(1, std::memory_order_relaxed);
  return PN_SUCCESS;
}

// Frees the handle when this was its last reference; NULL is a no-op. Destructors never throw.
template <class Handle>
pn_status releaseHandle(Handle* handle) noexcept {
  if (handle != nullptr && handle->references.fetch_sub(1, std::memory_order_acq_rel) == 1) delete handle;
  return PN_SUCCESS;
}

}  // namespace penumbra::api
