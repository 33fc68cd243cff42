#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
std::string locate(const std::string& file, int line, int column) {
  std::string s = file;
  if (line > 0) {
    s += (s.empty() ? "line " : ":") + std::to_string(line);
    if (column > 0) s += ":" + std::to_string(column);
  }
  return s;
}
}  // namespace

ParseError::ParseError(const std::string& file, int line, const std::string& message)
    : InputError(locate(file, line, 0) + ": " + message),
      file_(file),
      line_(line),
      message_(message) {}

ConfigError::ConfigError(const std::string& file, int line, int column, const std::string& path,
                         const std::string& message)
    : InputError([&] {
        std::string where = locate(file, line, column);
        std::string s = where.empty() ? std::string() : where + ": ";
        if (!path.empty()) s += path + ": ";
        return s + message;
      }()),
      file_(file),
      line_(line),
      column_(column),
      path_(path),
      message_(message) {}

PropertyNotFound::PropertyNotFound(const std::string& name, const std::string& available)
    : Error("no property '" + name + "'" +
            (available.empty() ? std::string(" (the container is empty)")
                               : " (it has: " + available + ")")),
      name_(name) {}

PropertyTypeMismatch::PropertyTypeMismatch(const std::string& name, const std::string& requested,
                                           const std::string& actual)
    : Error("property '" + name + "' holds " + actual + ", not the requested " + requested),
      name_(name) {}

ModuleError::ModuleError(const std::string& module, const std::string& type,
                         const std::string& message)
    : Error("module '" + module + "' (" + type + ") failed: " + message),
      module_(module),
      type_(type) {}

}  // namespace abi_v1
}  // namespace plugslam
