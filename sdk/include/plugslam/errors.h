#pragma once
// The SDK's typed exceptions. Every error a user can cause derives from plugslam::Error; the CLI
// maps InputError (bad file, config, argument) to exit code 2 and every other Error to 1.
#include <stdexcept>
#include <string>

namespace plugslam {
inline namespace abi_v1 {

/// Base of every plugslam exception.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// Bad input from the user: a file, a config, an argument. Exit code 2 at the CLI.
class InputError : public Error {
 public:
  explicit InputError(const std::string& what) : Error(what) {}
};

/// A malformed input file, with the file name and 1-based line (0 when unknown).
class ParseError : public InputError {
 public:
  ParseError(const std::string& file, int line, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_;
  std::string message_;
};

/// A configuration error located in a YAML file and in the pipeline
/// ("configs/a.yaml:12:7: pipeline.aligner.slices[1].max_distance: expected ...").
class ConfigError : public InputError {
 public:
  /// file may be empty (e.g. --set on the command line); line/column are 1-based, 0 if unknown.
  ConfigError(const std::string& file, int line, int column, const std::string& path,
              const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& path() const { return path_; }
  const std::string& message() const { return message_; }

 private:
  std::string file_;
  int line_, column_;
  std::string path_, message_;
};

/// A value that does not fit a parameter or property (wrong type, out of range); the builder
/// turns it into a ConfigError with the location.
class ValueError : public InputError {
 public:
  explicit ValueError(const std::string& what) : InputError(what) {}
};

/// A configurable's own validation failed on one of its parameters; `path` is relative to the
/// module ("max_distance", "slices[1].measurement") so the builder can point at the YAML node.
class ParamError : public ValueError {
 public:
  ParamError(const std::string& path, const std::string& message)
      : ValueError(path + ": " + message), path_(path), message_(message) {}
  const std::string& path() const { return path_; }
  const std::string& message() const { return message_; }

 private:
  std::string path_, message_;
};

/// A property container has no entry of that name.
class PropertyNotFound : public Error {
 public:
  PropertyNotFound(const std::string& name, const std::string& available);
  const std::string& name() const { return name_; }

 private:
  std::string name_;
};

/// A property container entry exists but holds another type than the one asked for.
class PropertyTypeMismatch : public Error {
 public:
  PropertyTypeMismatch(const std::string& name, const std::string& requested,
                       const std::string& actual);
  const std::string& name() const { return name_; }

 private:
  std::string name_;
};

/// A plugin could not be found, loaded, or was refused by the ABI checks.
class PluginError : public InputError {
 public:
  explicit PluginError(const std::string& what) : InputError(what) {}
};

/// A module failed while running; carries the plugin and module that threw.
class ModuleError : public Error {
 public:
  ModuleError(const std::string& module, const std::string& type, const std::string& message);
  const std::string& module() const { return module_; }
  const std::string& type() const { return type_; }

 private:
  std::string module_, type_;
};

}  // namespace abi_v1
}  // namespace plugslam
