// Format-independent part of serialization: the built-in value types, the factories and files.
#include "plugslam/archive.h"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "serialization/backends.h"

namespace plugslam {
inline namespace abi_v1 {

ArchiveFormat formatForPath(const std::string& path) {
  auto endsWith = [&](const char* suffix) {
    const std::size_t n = std::strlen(suffix);
    if (path.size() < n) return false;
    for (std::size_t i = 0; i < n; ++i) {
      if (std::tolower(static_cast<unsigned char>(path[path.size() - n + i])) != suffix[i]) {
        return false;
      }
    }
    return true;
  };
  return endsWith(".yaml") || endsWith(".yml") || endsWith(".json") ? ArchiveFormat::kText
                                                                    : ArchiveFormat::kBinary;
}

const char* formatName(ArchiveFormat format) {
  return format == ArchiveFormat::kBinary ? "binary" : "text";
}

std::unique_ptr<OutArchive> makeOutArchive(std::ostream& out, ArchiveFormat format) {
  return format == ArchiveFormat::kBinary ? serialization::makeBinaryOut(out)
                                          : serialization::makeTextOut(out);
}

std::unique_ptr<InArchive> makeInArchive(std::istream& in, ArchiveFormat format,
                                         const std::string& source) {
  return format == ArchiveFormat::kBinary ? serialization::makeBinaryIn(in, source)
                                          : serialization::makeTextIn(in, source);
}

void saveArchiveFile(const std::string& path, ArchiveFormat format,
                     const std::function<void(OutArchive&)>& write) {
  writeFileAtomically(path, [&](std::ostream& out) {
    auto ar = makeOutArchive(out, format);
    write(*ar);
    ar->finish();
  });
}

void loadArchiveFile(const std::string& path, const std::function<void(InArchive&)>& read) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open '" + path + "' for reading: " + std::strerror(errno));
  char magic[4] = {0, 0, 0, 0};
  in.read(magic, 4);
  const bool binary = in.gcount() == 4 && std::memcmp(magic, serialization::kBinaryMagic, 4) == 0;
  in.clear();
  in.seekg(0);
  auto ar = makeInArchive(in, binary ? ArchiveFormat::kBinary : ArchiveFormat::kText, path);
  read(*ar);
}

// ---- scalars ---------------------------------------------------------------------------------

void save(OutArchive& ar, bool value) { ar.writeBool(value); }
void load(InArchive& ar, bool& value) { value = ar.readBool(); }

void save(OutArchive& ar, std::int32_t value) { ar.writeInt(value); }
void load(InArchive& ar, std::int32_t& value) {
  const std::int64_t v = ar.readInt();
  if (v < std::numeric_limits<std::int32_t>::min() ||
      v > std::numeric_limits<std::int32_t>::max()) {
    ar.fail("integer " + std::to_string(v) + " does not fit a 32-bit signed integer");
  }
  value = static_cast<std::int32_t>(v);
}

void save(OutArchive& ar, std::int64_t value) { ar.writeInt(value); }
void load(InArchive& ar, std::int64_t& value) { value = ar.readInt(); }

void save(OutArchive& ar, std::uint32_t value) { ar.writeUInt(value); }
void load(InArchive& ar, std::uint32_t& value) {
  const std::uint64_t v = ar.readUInt();
  if (v > std::numeric_limits<std::uint32_t>::max()) {
    ar.fail("integer " + std::to_string(v) + " does not fit a 32-bit unsigned integer");
  }
  value = static_cast<std::uint32_t>(v);
}

void save(OutArchive& ar, std::uint64_t value) { ar.writeUInt(value); }
void load(InArchive& ar, std::uint64_t& value) { value = ar.readUInt(); }

void save(OutArchive& ar, double value) { ar.writeDouble(value); }
void load(InArchive& ar, double& value) { value = ar.readDouble(); }

void save(OutArchive& ar, const std::string& value) { ar.writeString(value); }
void save(OutArchive& ar, const char* value) { ar.writeString(value ? value : ""); }
void load(InArchive& ar, std::string& value) { value = ar.readString(); }

// ---- compact blobs ---------------------------------------------------------------------------

void save(OutArchive& ar, const std::vector<double>& value) {
  ar.writeDoubles(value.data(), value.size());
}

void load(InArchive& ar, std::vector<double>& value) {
  ar.readDoubles([&](std::size_t n) {
    value.resize(n);
    return value.data();
  });
}

namespace {

// std::vector<Eigen::Matrix<double, D, 1>> stores its points contiguously (D doubles each, no
// padding: static_assert below), so the blob is the vector's memory itself.
template <int D>
void savePoints(OutArchive& ar, const std::vector<Eigen::Matrix<double, D, 1>>& points) {
  static_assert(sizeof(Eigen::Matrix<double, D, 1>) == D * sizeof(double), "points are padded");
  ar.writeDoubles(points.empty() ? nullptr : points.front().data(), points.size() * D);
}

template <int D>
void loadPoints(InArchive& ar, std::vector<Eigen::Matrix<double, D, 1>>& points) {
  std::vector<double> flat;
  bool direct = false;
  ar.readDoubles([&](std::size_t n) -> double* {
    if (n % D == 0) {
      direct = true;
      points.resize(n / D);
      return points.empty() ? flat.data() : points.front().data();
    }
    flat.resize(n);  // read it, then report the bad length with the archive's position
    return flat.data();
  });
  if (!direct) {
    ar.fail("expected " + std::to_string(D) + " coordinates per point, found " +
            std::to_string(flat.size()) + " numbers (not a multiple of " + std::to_string(D) + ")");
  }
}

}  // namespace

void save(OutArchive& ar, const std::vector<Eigen::Vector2d>& value) { savePoints<2>(ar, value); }
void load(InArchive& ar, std::vector<Eigen::Vector2d>& value) { loadPoints<2>(ar, value); }
void save(OutArchive& ar, const std::vector<Eigen::Vector3d>& value) { savePoints<3>(ar, value); }
void load(InArchive& ar, std::vector<Eigen::Vector3d>& value) { loadPoints<3>(ar, value); }

// ---- matrices and isometries -----------------------------------------------------------------

namespace detail {

void saveMatrix(OutArchive& ar, const double* data, std::ptrdiff_t rows, std::ptrdiff_t cols,
                bool fixed_rows, bool fixed_cols) {
  const auto n = static_cast<std::size_t>(rows * cols);
  // A fixed shape, or a vector whose one free dimension the blob length gives, needs no header.
  if ((fixed_rows && fixed_cols) || (fixed_cols && cols == 1) || (fixed_rows && rows == 1)) {
    ar.writeDoubles(data, n);
    return;
  }
  ar.beginObject();
  ar.key("rows");
  ar.writeInt(rows);
  ar.key("cols");
  ar.writeInt(cols);
  ar.key("data");
  ar.writeDoubles(data, n);
  ar.endObject();
}

void loadMatrix(InArchive& ar, std::ptrdiff_t rows, std::ptrdiff_t cols,
                const std::function<double*(std::ptrdiff_t rows, std::ptrdiff_t cols)>& resize) {
  const bool fixed_rows = rows != Eigen::Dynamic;
  const bool fixed_cols = cols != Eigen::Dynamic;
  auto shape = [](std::ptrdiff_t r, std::ptrdiff_t c) {
    return (r == Eigen::Dynamic ? std::string("N") : std::to_string(r)) + "x" +
           (c == Eigen::Dynamic ? std::string("N") : std::to_string(c));
  };
  if ((fixed_rows && fixed_cols) || (fixed_cols && cols == 1) || (fixed_rows && rows == 1)) {
    std::size_t got = 0;
    bool ok = false;
    std::vector<double> scratch;
    ar.readDoubles([&](std::size_t n) -> double* {
      got = n;
      if (fixed_rows && fixed_cols) {
        ok = n == static_cast<std::size_t>(rows * cols);
      } else {
        ok = true;
      }
      if (!ok) {
        scratch.resize(n);
        return scratch.data();
      }
      const auto len = static_cast<std::ptrdiff_t>(n);
      return resize(fixed_rows ? rows : len, fixed_cols ? cols : len);
    });
    if (!ok) {
      ar.fail("expected a " + shape(rows, cols) + " matrix (" + std::to_string(rows * cols) +
              " numbers), found " + std::to_string(got) + " numbers");
    }
    return;
  }
  ar.beginObject();
  std::int64_t r = 0, c = 0;
  ar.key("rows");
  r = ar.readInt();
  ar.key("cols");
  c = ar.readInt();
  if (r < 0 || c < 0 || (fixed_rows && r != rows) || (fixed_cols && c != cols)) {
    ar.fail("expected a " + shape(rows, cols) + " matrix, found " + std::to_string(r) + "x" +
            std::to_string(c));
  }
  ar.key("data");
  std::size_t got = 0;
  bool ok = false;
  std::vector<double> scratch;
  ar.readDoubles([&](std::size_t n) -> double* {
    got = n;
    // Compare without multiplying first: r*c could overflow for a corrupted header.
    ok = (r == 0 || c == 0) ? n == 0
                            : (static_cast<std::uint64_t>(r) <= n &&
                               n / static_cast<std::uint64_t>(r) == static_cast<std::uint64_t>(c) &&
                               n % static_cast<std::uint64_t>(r) == 0);
    if (!ok) {
      scratch.resize(n);
      return scratch.data();
    }
    return resize(r, c);
  });
  if (!ok) {
    ar.fail("a " + std::to_string(r) + "x" + std::to_string(c) + " matrix does not match the " +
            std::to_string(got) + " numbers of its data");
  }
  ar.endObject();
}

}  // namespace detail

void save(OutArchive& ar, const Eigen::Isometry2d& value) {
  const Eigen::Matrix<double, 2, 3> top = value.matrix().topRows<2>();
  ar.writeDoubles(top.data(), 6);
}

void load(InArchive& ar, Eigen::Isometry2d& value) {
  Eigen::Matrix<double, 2, 3> top;
  load(ar, top);
  value.matrix().topRows<2>() = top;
  value.makeAffine();
}

void save(OutArchive& ar, const Eigen::Isometry3d& value) {
  const Eigen::Matrix<double, 3, 4> top = value.matrix().topRows<3>();
  ar.writeDoubles(top.data(), 12);
}

void load(InArchive& ar, Eigen::Isometry3d& value) {
  Eigen::Matrix<double, 3, 4> top;
  load(ar, top);
  value.matrix().topRows<3>() = top;
  value.makeAffine();
}

}  // namespace abi_v1
}  // namespace plugslam
