#include "rayspace/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cctype>
#include <cerrno>
#include <new>
#include <system_error>
#include <vector>

#include "rayspace/error.h"

namespace rayspace {
namespace {

constexpr std::size_t kChunk = std::size_t{1} << 20;

std::string ErrnoText(int err) { return std::generic_category().message(err); }

std::string KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string Amount(std::uint64_t bytes) {
  constexpr std::uint64_t kMiB = std::uint64_t{1} << 20, kGiB = std::uint64_t{1} << 30;
  if (bytes >= kGiB && bytes % kGiB == 0) return fmt::format("{} GiB", bytes / kGiB);
  if (bytes >= kMiB && bytes % kMiB == 0) return fmt::format("{} MiB", bytes / kMiB);
  return fmt::format("{} bytes", bytes);
}

class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

// Opening does not block (O_NONBLOCK: a FIFO without a writer would) and never makes a terminal
// the controlling one; the type is then taken from the open descriptor, not from the name.
int OpenRegular(const std::filesystem::path& path, const InputFile& spec, struct stat& st) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) ThrowInput("{}: cannot open {}: {}", path.string(), spec.what, ErrnoText(errno));
  if (::fstat(fd, &st) != 0) {
    const int err = errno;
    ::close(fd);
    ThrowInput("{}: cannot open {}: {}", path.string(), spec.what, ErrnoText(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    ThrowInput("{}: {} is {}, not a regular file", path.string(), spec.what, KindOf(st.st_mode));
  }
  return fd;
}

std::size_t ReadSome(const Descriptor& fd, void* buffer, std::size_t n, const std::filesystem::path& path,
                     const InputFile& spec) {
  for (;;) {
    const ssize_t got = ::read(fd.get(), buffer, n);
    if (got >= 0) return static_cast<std::size_t>(got);
    if (errno != EINTR) ThrowInput("{}: cannot read {}: {}", path.string(), spec.what, ErrnoText(errno));
  }
}

[[noreturn]] void TooLarge(const std::filesystem::path& path, const InputFile& spec, std::string_view how) {
  ThrowInput("{}: {} {} more than the {} rayspace reads", path.string(), spec.what, how, Amount(spec.max_bytes));
}

// The size is checked again while reading, since a file may grow (or a /proc file report 0)
// after fstat.
std::string ReadPlain(const Descriptor& fd, std::uint64_t size, const std::filesystem::path& path,
                      const InputFile& spec) {
  std::string data;
  data.reserve(static_cast<std::size_t>(size) + 1);
  for (;;) {
    // Into the reserved room first, so that a file of the size fstat gave is read without copying.
    const std::size_t old = data.size();
    const std::size_t room = data.capacity() > old ? data.capacity() - old : kChunk;
    data.resize(old + room);
    const std::size_t got = ReadSome(fd, data.data() + old, room, path, spec);
    data.resize(old + got);
    if (got == 0) return data;
    if (data.size() > spec.max_bytes) TooLarge(path, spec, "holds");
  }
}

class Inflater {
 public:
  Inflater() {
    // 16 + MAX_WBITS: gzip framing only, so that data which is not gzip is refused.
    if (inflateInit2(&zs_, 16 + MAX_WBITS) != Z_OK) throw std::bad_alloc();
  }
  ~Inflater() { inflateEnd(&zs_); }
  Inflater(const Inflater&) = delete;
  Inflater& operator=(const Inflater&) = delete;
  z_stream& z() { return zs_; }

 private:
  z_stream zs_{};
};

// Inflates the whole file from its start, handing each decompressed piece to `sink`; refuses corrupt,
// truncated or empty data and more than the bound (counted as it goes, so nothing beyond the bound is
// ever decompressed). Concatenated gzip members are one file, as gzip itself reads them. Returns the
// decompressed size.
template <typename Sink>
std::uint64_t Inflate(const Descriptor& fd, const std::filesystem::path& path, const InputFile& spec, Sink&& sink) {
  if (::lseek(fd.get(), 0, SEEK_SET) != 0) ThrowInput("{}: cannot read {}: {}", path.string(), spec.what, ErrnoText(errno));
  Inflater inflater;
  z_stream& zs = inflater.z();
  std::vector<unsigned char> in(kChunk), out(kChunk);
  std::uint64_t compressed = 0, total = 0;
  bool eof = false;
  int ret = Z_OK;
  for (;;) {
    if (zs.avail_in == 0 && !eof) {
      const std::size_t got = ReadSome(fd, in.data(), in.size(), path, spec);
      eof = got == 0;
      compressed += got;
      if (compressed > spec.max_bytes) TooLarge(path, spec, "holds");
      zs.next_in = in.data();
      zs.avail_in = static_cast<uInt>(got);
    }
    if (zs.avail_in == 0 && eof) {
      if (compressed == 0) ThrowInput("{}: {} is empty, not gzip data", path.string(), spec.what);
      if (ret != Z_STREAM_END) ThrowInput("{}: {} is truncated gzip data (it ends inside the stream)", path.string(), spec.what);
      return total;
    }
    if (ret == Z_STREAM_END) inflateReset(&zs);
    zs.next_out = out.data();
    zs.avail_out = static_cast<uInt>(out.size());
    ret = inflate(&zs, Z_NO_FLUSH);
    if (ret == Z_MEM_ERROR) throw std::bad_alloc();
    if (ret == Z_DATA_ERROR || ret == Z_NEED_DICT || ret == Z_STREAM_ERROR)
      ThrowInput("{}: {} is not valid gzip data ({})", path.string(), spec.what, zs.msg ? zs.msg : "corrupt stream");
    const std::size_t n = out.size() - zs.avail_out;
    if (total + n > spec.max_bytes) TooLarge(path, spec, "decompresses to");
    sink(std::string_view(reinterpret_cast<const char*>(out.data()), n), total);
    total += n;
  }
}

// Two passes: the first checks the data (size, framing, and for text a NUL byte, each refused where
// it is met) and keeps nothing; the second keeps it in a string of exactly its size. A bomb or a file
// of NUL bytes fails after reading no more than the bound or up to the first NUL, and memory never
// exceeds the decompressed size (a growing string would peak at twice it).
std::string Gunzip(const Descriptor& fd, const std::filesystem::path& path, const InputFile& spec) {
  const std::uint64_t size = Inflate(fd, path, spec, [&](std::string_view piece, std::uint64_t at) {
    if (!spec.text) return;
    if (const std::size_t nul = piece.find('\0'); nul != std::string_view::npos)
      ThrowInput("{}: {} holds a NUL byte at decompressed byte {}, and it is a text file", path.string(), spec.what,
                 at + nul + 1);
  });
  std::string data;
  data.reserve(static_cast<std::size_t>(size));
  Inflate(fd, path, spec, [&](std::string_view piece, std::uint64_t) {
    if (data.size() + piece.size() > size) ThrowInput("{}: {} changed while it was read", path.string(), spec.what);
    data.append(piece);
  });
  if (data.size() != size) ThrowInput("{}: {} changed while it was read", path.string(), spec.what);
  return data;
}

}  // namespace

std::string ReadInputFile(const std::filesystem::path& path, const InputFile& spec) {
  struct stat st {};
  const Descriptor fd(OpenRegular(path, spec, st));
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > spec.max_bytes) TooLarge(path, spec, fmt::format("is {} bytes,", size));
  if (spec.gzip == Gzip::kByExtension && IsGzipName(path)) return Gunzip(fd, path, spec);
  return ReadPlain(fd, size, path, spec);
}

std::string NotRegularFile(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return errno == ENOENT ? "does not exist" : "cannot be read: " + ErrnoText(errno);
  return S_ISREG(st.st_mode) ? std::string() : "is " + KindOf(st.st_mode) + ", not a regular file";
}

bool IsGzipName(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gz";
}

std::string StemWithoutGz(const std::filesystem::path& path) {
  std::filesystem::path name = path.filename();
  if (IsGzipName(name)) name = name.stem();
  return name.stem().string();
}

}  // namespace rayspace
