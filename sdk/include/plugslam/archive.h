#pragma once
// One archive interface for every serialized thing (containers, local maps, the graph), with a
// binary back-end and a text (YAML) back-end behind it. A value is written into a "slot": the
// root, a named field of an object (after key()), or the next element of an array. Readers find
// object fields by name, so the order of fields in a file does not matter.
//
// Value types become serializable through free functions found by overload resolution or ADL:
//   void save(plugslam::OutArchive&, const T&);
//   void load(plugslam::InArchive&, T&);
// The overloads for the built-in types are declared here, before any template that calls them,
// because two-phase lookup only sees plugslam overloads for std/Eigen types at the definition.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

/// Writes values into one archive (binary or text); call finish() once the root value is written.
class OutArchive {
 public:
  virtual ~OutArchive() = default;

  /// Opens an object: a set of named fields, each introduced by key().
  virtual void beginObject() = 0;
  /// Closes the innermost object.
  virtual void endObject() = 0;
  /// Names the field the next value is written to; only valid directly inside an object.
  virtual void key(const std::string& name) = 0;
  /// Opens an array of exactly `size` elements.
  virtual void beginArray(std::size_t size) = 0;
  /// Closes the innermost array; throws std::logic_error if fewer elements than announced.
  virtual void endArray() = 0;

  /// Writes a boolean.
  virtual void writeBool(bool value) = 0;
  /// Writes a signed integer.
  virtual void writeInt(std::int64_t value) = 0;
  /// Writes an unsigned integer.
  virtual void writeUInt(std::uint64_t value) = 0;
  /// Writes a double (bit-exact in both back-ends, NaN and infinities included).
  virtual void writeDouble(double value) = 0;
  /// Writes a string (the text back-end requires valid UTF-8).
  virtual void writeString(const std::string& value) = 0;
  /// Writes n doubles as one compact blob (one length, then the raw values).
  virtual void writeDoubles(const double* data, std::size_t n) = 0;

  /// Completes the archive and flushes it to the stream; the archive is unusable afterwards.
  virtual void finish() = 0;

  /// Writes `value` into the field `name` of the current object.
  template <class T>
  OutArchive& field(const std::string& name, const T& value);
};

/// Reads values from one archive; malformed input throws plugslam::ParseError.
class InArchive {
 public:
  virtual ~InArchive() = default;

  /// Enters an object (ParseError if the next value is not an object).
  virtual void beginObject() = 0;
  /// Leaves the innermost object (fields not read are skipped).
  virtual void endObject() = 0;
  /// Selects the field `name` of the current object for the next read; ParseError naming the
  /// field and the fields present when it is missing.
  virtual void key(const std::string& name) = 0;
  /// True when the current object has a field `name`.
  virtual bool hasKey(const std::string& name) const = 0;
  /// The field names of the current object, in file order.
  virtual std::vector<std::string> keys() const = 0;
  /// Enters an array and returns its length.
  virtual std::size_t beginArray() = 0;
  /// Leaves the innermost array (elements not read are skipped).
  virtual void endArray() = 0;

  /// Reads a boolean.
  virtual bool readBool() = 0;
  /// Reads a signed integer.
  virtual std::int64_t readInt() = 0;
  /// Reads an unsigned integer.
  virtual std::uint64_t readUInt() = 0;
  /// Reads a double.
  virtual double readDouble() = 0;
  /// Reads a string.
  virtual std::string readString() = 0;
  /// Reads a blob of doubles: `storage(n)` is called once with the count and must return room
  /// for n doubles (the count is checked against the input size before storage is asked for).
  virtual void readDoubles(const std::function<double*(std::size_t n)>& storage) = 0;

  /// Throws a ParseError at the current position (file, line if known, field path); for load()
  /// overloads that find a value they cannot accept.
  [[noreturn]] virtual void fail(const std::string& message) const = 0;

  /// Reads the field `name` of the current object into `value`.
  template <class T>
  InArchive& field(const std::string& name, T& value);
};

/// The two back-ends.
enum class ArchiveFormat {
  kBinary,  ///< compact little-endian, magic + version + length + CRC-32 header
  kText,    ///< YAML (a reader also accepts JSON)
};

/// The back-end a file name suggests: .yaml/.yml/.json are text, everything else binary.
ArchiveFormat formatForPath(const std::string& path);
/// Human-readable name of a format ("binary", "text").
const char* formatName(ArchiveFormat format);

/// An archive writing to `out` (which must outlive it).
std::unique_ptr<OutArchive> makeOutArchive(std::ostream& out, ArchiveFormat format);
/// An archive reading one archive from `in`; `source` names the input in error messages.
/// The binary reader consumes exactly one archive (several can follow each other in a stream) and
/// validates its header, length and checksum here (ParseError); the text reader reads `in` to
/// its end.
std::unique_ptr<InArchive> makeInArchive(std::istream& in, ArchiveFormat format,
                                         const std::string& source = "<stream>");

/// Writes a file atomically through an archive: temp file in the same folder, fsync, rename.
void saveArchiveFile(const std::string& path, ArchiveFormat format,
                     const std::function<void(OutArchive&)>& write);
/// Reads a file through an archive; the format is detected from the file's first bytes.
void loadArchiveFile(const std::string& path, const std::function<void(InArchive&)>& read);

// ---- built-in value types --------------------------------------------------------------------

/// Serializes a bool.
void save(OutArchive& ar, bool value);
/// Deserializes a bool.
void load(InArchive& ar, bool& value);
/// Serializes a 32-bit signed integer.
void save(OutArchive& ar, std::int32_t value);
/// Deserializes a 32-bit signed integer (ParseError when out of range).
void load(InArchive& ar, std::int32_t& value);
/// Serializes a 64-bit signed integer.
void save(OutArchive& ar, std::int64_t value);
/// Deserializes a 64-bit signed integer.
void load(InArchive& ar, std::int64_t& value);
/// Serializes a 32-bit unsigned integer.
void save(OutArchive& ar, std::uint32_t value);
/// Deserializes a 32-bit unsigned integer (ParseError when out of range).
void load(InArchive& ar, std::uint32_t& value);
/// Serializes a 64-bit unsigned integer.
void save(OutArchive& ar, std::uint64_t value);
/// Deserializes a 64-bit unsigned integer.
void load(InArchive& ar, std::uint64_t& value);
/// Serializes a double.
void save(OutArchive& ar, double value);
/// Deserializes a double.
void load(InArchive& ar, double& value);
/// Serializes a string.
void save(OutArchive& ar, const std::string& value);
/// Serializes a string literal (without this overload it would silently become a bool).
void save(OutArchive& ar, const char* value);
/// Deserializes a string.
void load(InArchive& ar, std::string& value);
/// Serializes a vector of doubles as one compact blob.
void save(OutArchive& ar, const std::vector<double>& value);
/// Deserializes a vector of doubles.
void load(InArchive& ar, std::vector<double>& value);
/// Serializes 2D points as one compact blob (x0 y0 x1 y1 ...).
void save(OutArchive& ar, const std::vector<Eigen::Vector2d>& value);
/// Deserializes 2D points (ParseError when the blob length is odd).
void load(InArchive& ar, std::vector<Eigen::Vector2d>& value);
/// Serializes 3D points as one compact blob (x0 y0 z0 x1 ...).
void save(OutArchive& ar, const std::vector<Eigen::Vector3d>& value);
/// Deserializes 3D points (ParseError when the blob length is not a multiple of 3).
void load(InArchive& ar, std::vector<Eigen::Vector3d>& value);
/// Serializes a 2D isometry as the 6 doubles of its top 2x3 block (column-major).
void save(OutArchive& ar, const Eigen::Isometry2d& value);
/// Deserializes a 2D isometry.
void load(InArchive& ar, Eigen::Isometry2d& value);
/// Serializes a 3D isometry as the 12 doubles of its top 3x4 block (column-major).
void save(OutArchive& ar, const Eigen::Isometry3d& value);
/// Deserializes a 3D isometry.
void load(InArchive& ar, Eigen::Isometry3d& value);

namespace detail {
/// Writes a column-major matrix: a plain blob when the shape is fixed or a dynamic column vector,
/// otherwise an object {rows, cols, data}.
void saveMatrix(OutArchive& ar, const double* data, std::ptrdiff_t rows, std::ptrdiff_t cols,
                bool fixed_rows, bool fixed_cols);
/// Reads what saveMatrix wrote; `resize(rows, cols)` returns column-major storage. `rows`/`cols`
/// are the compile-time sizes (Eigen::Dynamic when free) and are checked (ParseError).
void loadMatrix(InArchive& ar, std::ptrdiff_t rows, std::ptrdiff_t cols,
                const std::function<double*(std::ptrdiff_t rows, std::ptrdiff_t cols)>& resize);
}  // namespace detail

/// Serializes any double-valued Eigen matrix or vector (fixed or dynamic size).
template <int R, int C, int O, int MR, int MC>
void save(OutArchive& ar, const Eigen::Matrix<double, R, C, O, MR, MC>& m) {
  if constexpr (static_cast<bool>(O & Eigen::RowMajor) && R != 1 && C != 1) {
    // One on-disk layout (column-major) for both storage orders.
    const Eigen::Matrix<double, R, C, Eigen::ColMajor, MR, MC> cm = m;
    detail::saveMatrix(ar, cm.data(), cm.rows(), cm.cols(), R != Eigen::Dynamic,
                       C != Eigen::Dynamic);
  } else {
    detail::saveMatrix(ar, m.data(), m.rows(), m.cols(), R != Eigen::Dynamic, C != Eigen::Dynamic);
  }
}

/// Deserializes any double-valued Eigen matrix or vector (fixed or dynamic size).
template <int R, int C, int O, int MR, int MC>
void load(InArchive& ar, Eigen::Matrix<double, R, C, O, MR, MC>& m) {
  if constexpr (static_cast<bool>(O & Eigen::RowMajor) && R != 1 && C != 1) {
    Eigen::Matrix<double, R, C, Eigen::ColMajor, MR, MC> cm;
    detail::loadMatrix(ar, R, C, [&](std::ptrdiff_t rows, std::ptrdiff_t cols) {
      cm.resize(rows, cols);
      return cm.data();
    });
    m = cm;
  } else {
    detail::loadMatrix(ar, R, C, [&](std::ptrdiff_t rows, std::ptrdiff_t cols) {
      m.resize(rows, cols);
      return m.data();
    });
  }
}

// Generic containers: declared first so each can hold the other.
template <class T>
void save(OutArchive& ar, const std::vector<T>& value);
template <class T>
void load(InArchive& ar, std::vector<T>& value);
template <class T>
void save(OutArchive& ar, const std::map<std::string, T>& value);
template <class T>
void load(InArchive& ar, std::map<std::string, T>& value);

/// Serializes a vector as an array of its elements.
template <class T>
void save(OutArchive& ar, const std::vector<T>& value) {
  ar.beginArray(value.size());
  for (const auto& v : value) save(ar, v);
  ar.endArray();
}

/// Deserializes a vector.
template <class T>
void load(InArchive& ar, std::vector<T>& value) {
  const std::size_t n = ar.beginArray();
  value.clear();
  // n is bounded by the input size, but sizeof(T) may be large: cap what is reserved up front.
  value.reserve(n < 4096 ? n : 4096);
  for (std::size_t i = 0; i < n; ++i) {
    T v{};
    load(ar, v);
    value.push_back(std::move(v));
  }
  ar.endArray();
}

/// Serializes a string-keyed map as an object.
template <class T>
void save(OutArchive& ar, const std::map<std::string, T>& value) {
  ar.beginObject();
  for (const auto& [k, v] : value) {
    ar.key(k);
    save(ar, v);
  }
  ar.endObject();
}

/// Deserializes a string-keyed map.
template <class T>
void load(InArchive& ar, std::map<std::string, T>& value) {
  ar.beginObject();
  value.clear();
  for (const auto& k : ar.keys()) {
    ar.key(k);
    load(ar, value[k]);
  }
  ar.endObject();
}

namespace detail {
/// Calls the save() overload for T from a context where member functions named save would hide
/// the free functions.
template <class T>
void callSave(OutArchive& ar, const T& value) {
  save(ar, value);
}
/// Calls the load() overload for T (see callSave).
template <class T>
void callLoad(InArchive& ar, T& value) {
  load(ar, value);
}

template <class T, class = void>
struct HasSave : std::false_type {};
template <class T>
struct HasSave<T,
               std::void_t<decltype(save(std::declval<OutArchive&>(), std::declval<const T&>()))>>
    : std::true_type {};
template <class T, class = void>
struct HasLoad : std::false_type {};
template <class T>
struct HasLoad<T, std::void_t<decltype(load(std::declval<InArchive&>(), std::declval<T&>()))>>
    : std::true_type {};
}  // namespace detail

/// True when T has save() and load() overloads. For std::vector<T> and std::map<std::string, T>
/// only the outer overload is checked; a T without overloads fails when they are instantiated.
template <class T>
constexpr bool kIsSerializable = detail::HasSave<T>::value&& detail::HasLoad<T>::value;

template <class T>
OutArchive& OutArchive::field(const std::string& name, const T& value) {
  key(name);
  detail::callSave(*this, value);
  return *this;
}

template <class T>
InArchive& InArchive::field(const std::string& name, T& value) {
  key(name);
  detail::callLoad(*this, value);
  return *this;
}

/// Saves one value as the root of a file, atomically (see saveArchiveFile).
template <class T>
void saveFile(const std::string& path, const T& value, ArchiveFormat format) {
  saveArchiveFile(path, format, [&](OutArchive& ar) { detail::callSave(ar, value); });
}

/// Loads the root value of a file written by saveFile (either format).
template <class T>
void loadFile(const std::string& path, T& value) {
  loadArchiveFile(path, [&](InArchive& ar) { detail::callLoad(ar, value); });
}

}  // namespace abi_v1
}  // namespace plugslam
