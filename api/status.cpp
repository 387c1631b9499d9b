// Status names, the thread-local error state and the exception-to-status mapping of the C API.
#include <new>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>

#include "api/guard.h"
#include "host/cl/error.h"
#include "host/pipeline/memory_plan.h"
#include "host/scene/load_options.h"
#include "host/techniques/technique.h"
#include "host/version.h"

namespace penumbra::api {
namespace {

// One per thread: what the last failing call on it said.
thread_local std::string lastMessage;
thread_local cl_int lastClError = CL_SUCCESS;

// The core's messages name a technique's parameters as the command line spells them ("--pcf-radius: -3 is outside
// [0, 16]"); a library caller sets them by name (pn_params_set(params, "pcf-radius", ...)), so the message does too.
std::string libraryTerms(std::string_view message) {
  static const std::set<std::string, std::less<>> names = [] {
    std::set<std::string, std::less<>> all;
    for (const TechniqueInfo& technique : techniques())
      for (const ParamSpec& spec : technique.params) all.insert(spec.name);
    return all;
  }();
  std::string out;
  size_t i = 0;
  while (i < message.size()) {
    const size_t dashes = message.find("--", i);
    if (dashes == std::string_view::npos) break;
    size_t end = dashes + 2;
    while (end < message.size() && (std::islower(static_cast<unsigned char>(message[end])) ||
                                    std::isdigit(static_cast<unsigned char>(message[end])) || message[end] == '-'))
      ++end;
    const bool parameter = names.count(message.substr(dashes + 2, end - dashes - 2)) != 0;
    out.append(message.substr(i, dashes - i));
    out.append(message.substr(parameter ? dashes + 2 : dashes, end - (parameter ? dashes + 2 : dashes)));
    i = end;
  }
  out.append(message.substr(i));
  return out;
}

}  // namespace

pn_status fail(pn_status status, const char* message, cl_int clError) noexcept {
  try {
    lastMessage = libraryTerms(message);
  } catch (...) {
    lastMessage.clear();  // out of memory for the message itself: the status still says what happened
  }
  lastClError = clError;
  return status;
}

pn_status failCurrentException() noexcept {
  try {
    throw;
  } catch (const BuildError& e) {
    return fail(PN_ERROR_BUILD, e.what());
  } catch (const ClError& e) {
    return fail(PN_ERROR_OPENCL, e.what(), e.code());
  } catch (const NoDeviceError& e) {
    return fail(PN_ERROR_NO_DEVICE, e.what());
  } catch (const SceneError& e) {
    return fail(PN_ERROR_SCENE, e.what());
  } catch (const MemoryError& e) {  // the frame's memory plan refused it, or an allocation failed in a stage
    return fail(PN_ERROR_OUT_OF_MEMORY, e.what());
  } catch (const std::logic_error& e) {  // invalid_argument, out_of_range, length_error, domain_error
    return fail(PN_ERROR_INVALID_ARGUMENT, e.what());
  } catch (const std::bad_alloc&) {
    return fail(PN_ERROR_OUT_OF_MEMORY, "out of host memory");
  } catch (const std::exception& e) {
    return fail(PN_ERROR_RUNTIME, e.what());
  } catch (...) {
    return fail(PN_ERROR_UNKNOWN, "an exception that is not a std::exception");
  }
}

}  // namespace penumbra::api

extern "C" {

const char* pn_status_name(pn_status status) {
  switch (status) {
    case PN_SUCCESS:
      return "PN_SUCCESS";
    case PN_ERROR_INVALID_ARGUMENT:
      return "PN_ERROR_INVALID_ARGUMENT";
    case PN_ERROR_NO_DEVICE:
      return "PN_ERROR_NO_DEVICE";
    case PN_ERROR_OPENCL:
      return "PN_ERROR_OPENCL";
    case PN_ERROR_BUILD:
      return "PN_ERROR_BUILD";
    case PN_ERROR_SCENE:
      return "PN_ERROR_SCENE";
    case PN_ERROR_RUNTIME:
      return "PN_ERROR_RUNTIME";
    case PN_ERROR_OUT_OF_MEMORY:
      return "PN_ERROR_OUT_OF_MEMORY";
    case PN_ERROR_UNKNOWN:
      return "PN_ERROR_UNKNOWN";
    case PN_STATUS_MAX_ENUM:  // not a status
      break;
  }
  return "PN_UNKNOWN_STATUS";
}

const char* pn_last_error_message(void) { return penumbra::api::lastMessage.c_str(); }

cl_int pn_last_cl_error(void) { return penumbra::api::lastClError; }

const char* pn_version(void) { return penumbra::version().data(); }  // a literal: null-terminated

}  // extern "C"
