#include "plugslam/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ostream>
#include <random>
#include <streambuf>
#include <vector>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {

std::string systemError(int err) { return std::strerror(err); }

// A buffered streambuf over a POSIX file descriptor; remembers the first write error.
class FdBuf final : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd), buffer_(1 << 16) {
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!flushBuffer()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return flushBuffer() ? 0 : -1; }

 private:
  bool flushBuffer() {
    const char* p = pbase();
    std::size_t n = static_cast<std::size_t>(pptr() - pbase());
    while (n > 0) {
      const ssize_t w = ::write(fd_, p, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        if (error_ == 0) error_ = errno;
        return false;
      }
      p += w;
      n -= static_cast<std::size_t>(w);
    }
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return true;
  }

  int fd_;
  std::vector<char> buffer_;
  int error_ = 0;
};

std::string folderOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

// Opens a fresh temp file next to `path`. O_EXCL with mode 0666 (not mkstemp's 0600) so the
// result gets the permissions the umask gives any ordinary new file.
int openTemp(const std::string& path, std::string& temp) {
  static const char kAlphabet[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
  std::random_device rd;
  std::mt19937_64 rng((static_cast<std::uint64_t>(rd()) << 32) ^ rd() ^
                      static_cast<std::uint64_t>(::getpid()));
  for (int attempt = 0; attempt < 100; ++attempt) {
    temp = path + ".tmp-";
    for (int i = 0; i < 6; ++i) temp += kAlphabet[rng() % (sizeof(kAlphabet) - 1)];
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) return fd;
    if (errno != EEXIST) {
      throw InputError("cannot write '" + path + "': cannot create a file in '" + folderOf(path) +
                       "': " + systemError(errno));
    }
  }
  throw InputError("cannot write '" + path + "': no free temp file name in '" + folderOf(path) +
                   "'");
}

}  // namespace

void writeFileAtomically(const std::string& path,
                         const std::function<void(std::ostream& out)>& write) {
  if (path.empty()) throw InputError("cannot write a file with an empty path");
  std::string temp;
  const int fd = openTemp(path, temp);
  auto abandon = [&] {
    ::close(fd);
    ::unlink(temp.c_str());
  };
  try {
    FdBuf buf(fd);
    std::ostream out(&buf);
    write(out);
    out.flush();
    if (!out || buf.error() != 0) {
      throw InputError("cannot write '" + path + "': " +
                       (buf.error() != 0 ? systemError(buf.error()) : std::string("stream error")));
    }
  } catch (...) {
    abandon();
    throw;
  }
  if (::fsync(fd) != 0) {
    const int err = errno;
    abandon();
    throw InputError("cannot write '" + path + "': fsync failed: " + systemError(err));
  }
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(temp.c_str());
    throw InputError("cannot write '" + path + "': close failed: " + systemError(err));
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(temp.c_str());
    throw InputError("cannot write '" + path + "': rename failed: " + systemError(err));
  }
  // Make the rename itself durable; failure here leaves a complete file, so it is not an error.
  const int dir = ::open(folderOf(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

}  // namespace abi_v1
}  // namespace plugslam
