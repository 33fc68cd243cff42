#pragma once
// The plugin ABI. A plugin exports exactly one C symbol, `plugslam_plugin_descriptor`, returning
// a descriptor the host checks (magic, ABI version, build fingerprint) before it calls anything
// else in the plugin. Write a plugin as:
//
//   #include "plugslam/plugin.h"
//   PLUGSLAM_PLUGIN("laser2d", "1.0.0", "2D laser scans") {
//     registrar.add<ScanPreprocessor>("ScanPreprocessor", "laser scan -> 2D points");
//   }
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>

#include "plugslam/registry.h"
#include "plugslam/version.h"

#define PLUGSLAM_STR_(x) #x
#define PLUGSLAM_STR(x) PLUGSLAM_STR_(x)

#if defined(__clang__)
#define PLUGSLAM_COMPILER_ID "clang-" PLUGSLAM_STR(__clang_major__)
#elif defined(__GNUC__)
#define PLUGSLAM_COMPILER_ID "gcc-" PLUGSLAM_STR(__GNUC__)
#else
#define PLUGSLAM_COMPILER_ID "unknown"
#endif
#if defined(_GLIBCXX_USE_CXX11_ABI)
#define PLUGSLAM_CXX11_ABI PLUGSLAM_STR(_GLIBCXX_USE_CXX11_ABI)
#else
#define PLUGSLAM_CXX11_ABI "none"
#endif
#if defined(NDEBUG)
#define PLUGSLAM_NDEBUG "1"
#else
#define PLUGSLAM_NDEBUG "0"
#endif

/// What must match between the host and a plugin for C++ objects to cross the boundary.
/// Semicolon-separated key=value pairs, compared key by key.
#define PLUGSLAM_BUILD_FINGERPRINT                                                              \
  "compiler=" PLUGSLAM_COMPILER_ID ";cxx11abi=" PLUGSLAM_CXX11_ABI                              \
  ";eigen=" PLUGSLAM_STR(EIGEN_WORLD_VERSION) "." PLUGSLAM_STR(EIGEN_MAJOR_VERSION) "." PLUGSLAM_STR( \
      EIGEN_MINOR_VERSION) ";eigen_align=" PLUGSLAM_STR(EIGEN_MAX_STATIC_ALIGN_BYTES)           \
      ";ndebug=" PLUGSLAM_NDEBUG

extern "C" {
/// The descriptor a plugin exports; a plain C struct so any host can read it safely.
struct PlugslamPluginDescriptor {
  uint64_t magic;                 ///< kPlugslamPluginMagic
  uint32_t abi_major;             ///< PLUGSLAM_ABI_MAJOR the plugin was built with
  uint32_t abi_minor;             ///< PLUGSLAM_ABI_MINOR the plugin was built with
  const char* sdk_version;        ///< SDK version string the plugin was built against
  const char* build_fingerprint;  ///< PLUGSLAM_BUILD_FINGERPRINT of the plugin's build
  const char* name;               ///< plugin name, the prefix of its type names
  const char* version;            ///< plugin version
  const char* description;        ///< one line
  /// Registers the plugin's types into the plugslam::Registrar behind `registrar`; returns 0 on
  /// success, otherwise writes a message into err (at most err_size bytes) and returns non-zero.
  int (*register_types)(void* registrar, char* err, size_t err_size);
};
/// Signature of the exported entry point.
typedef const PlugslamPluginDescriptor* (*PlugslamDescriptorFn)();
}

/// Magic number at the start of every descriptor ("PLUGSLAM" in ASCII).
constexpr uint64_t kPlugslamPluginMagic = 0x504c5547534c414dULL;
/// Name of the exported entry point.
constexpr const char* kPlugslamDescriptorSymbol = "plugslam_plugin_descriptor";

namespace plugslam {
inline namespace abi_v1 {
namespace detail {
/// Calls a plugin's register body, turning any exception into an error message.
inline int callRegister(void (*body)(Registrar&), void* registrar, char* err,
                        size_t err_size) noexcept {
  try {
    body(*static_cast<Registrar*>(registrar));
    return 0;
  } catch (const std::exception& e) {
    if (err_size > 0) {
      std::strncpy(err, e.what(), err_size - 1);
      err[err_size - 1] = '\0';
    }
  } catch (...) {
    if (err_size > 0) std::strncpy(err, "unknown exception", err_size - 1);
  }
  return 1;
}
}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam

/// Defines the plugin's descriptor entry; the block that follows is the register function and
/// sees `plugslam::Registrar& registrar`.
#define PLUGSLAM_PLUGIN(NAME, VERSION, DESCRIPTION)                                            \
  static void plugslamRegisterTypes(::plugslam::Registrar& registrar);                         \
  static int plugslamRegisterEntry(void* r, char* err, size_t n) noexcept {                    \
    return ::plugslam::detail::callRegister(&plugslamRegisterTypes, r, err, n);                \
  }                                                                                            \
  extern "C" __attribute__((visibility("default"))) const PlugslamPluginDescriptor*            \
  plugslam_plugin_descriptor() {                                                               \
    static const PlugslamPluginDescriptor descriptor = {                                       \
        kPlugslamPluginMagic, PLUGSLAM_ABI_MAJOR,         PLUGSLAM_ABI_MINOR,                  \
        PLUGSLAM_VERSION_STRING, PLUGSLAM_BUILD_FINGERPRINT, NAME,                             \
        VERSION,              DESCRIPTION,                &plugslamRegisterEntry};             \
    return &descriptor;                                                                        \
  }                                                                                            \
  static void plugslamRegisterTypes(::plugslam::Registrar& registrar)

namespace plugslam {
inline namespace abi_v1 {
/// The host's own build fingerprint (from the SDK's build).
const char* hostBuildFingerprint();
}  // namespace abi_v1
}  // namespace plugslam
