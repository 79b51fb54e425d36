#include "rayspace/output_file.h"

#include <atomic>
#include <climits>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>
#include <optional>
#include <utility>

#include <cerrno>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <dirent.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "rayspace/error.h"

namespace rayspace {
namespace {

namespace fs = std::filesystem;

// The temporary files and directories alive now, for the signal handler: it may only read plain
// memory and make async-signal-safe calls, so the paths live in fixed slots, each published by its
// `used` flag.
enum class TempKind : unsigned char { kFile, kDirectory, kContents };  // kContents: empty it, keep it
struct TempSlot {
  std::atomic<bool> used{false};
  TempKind kind = TempKind::kFile;
  char path[PATH_MAX] = {};
};
constexpr int kTempSlots = 64;

// The process groups of the shell commands running now (RunShellCommand), 0 in a free slot: the
// handler ends them before it removes the temporaries they might write into.
constexpr int kChildSlots = 64;
std::atomic<pid_t> g_children[kChildSlots];
TempSlot g_temps[kTempSlots];
std::mutex g_temps_mutex;  // slot allocation only; the handler never takes it
std::atomic<bool> g_stdout_taken{false};

// Removes the tree under the open directory `dir` with async-signal-safe calls only (getdents64,
// openat, unlinkat, close): no allocation, no locks. Closes `dir`. A tree deeper than kMaxDepth
// keeps what lies below (rayspace's own trees are three levels deep).
void RemoveTreeAt(int dir, int depth) noexcept {
  constexpr int kMaxDepth = 16;
  alignas(8) char buffer[4096];
  for (;;) {
    const long n = ::syscall(SYS_getdents64, dir, buffer, sizeof buffer);
    if (n <= 0) break;
    bool removed = false;
    for (long off = 0; off < n;) {
      struct Entry {
        std::uint64_t ino;
        std::int64_t next;
        unsigned short reclen;
        unsigned char type;
        char name[1];
      };
      const auto* e = reinterpret_cast<const Entry*>(buffer + off);
      off += e->reclen;
      if (e->name[0] == '.' && (e->name[1] == 0 || (e->name[1] == '.' && e->name[2] == 0))) continue;
      if (e->type == DT_DIR && depth < kMaxDepth) {
        const int sub = ::openat(dir, e->name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (sub >= 0) RemoveTreeAt(sub, depth + 1);
        ::unlinkat(dir, e->name, AT_REMOVEDIR);
      } else {
        ::unlinkat(dir, e->name, 0);
      }
      removed = true;
    }
    // Entries removed while listing: read the directory again from its start.
    if (removed) ::lseek(dir, 0, SEEK_SET);
  }
  ::close(dir);
}

void RemoveTemps() noexcept {
  for (TempSlot& s : g_temps) {
    if (!s.used.load(std::memory_order_acquire)) continue;
    if (s.kind == TempKind::kFile) {
      ::unlink(s.path);
      continue;
    }
    const int dir = ::open(s.path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (dir >= 0) RemoveTreeAt(dir, 0);
    if (s.kind == TempKind::kDirectory) ::rmdir(s.path);
  }
}

// Whether a watched directory still holds something (or, removed whole, still exists): async-signal-safe.
bool TempsLeft() noexcept {
  for (TempSlot& s : g_temps) {
    if (!s.used.load(std::memory_order_acquire) || s.kind == TempKind::kFile) continue;
    const int dir = ::open(s.path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (dir < 0) continue;
    if (s.kind == TempKind::kDirectory) {
      ::close(dir);
      return true;
    }
    alignas(8) char buffer[1024];
    const long n = ::syscall(SYS_getdents64, dir, buffer, sizeof buffer);
    ::close(dir);
    // "." and ".." take at most 48 bytes of entries; anything more is a file left.
    if (n > 48) return true;
  }
  return false;
}

extern "C" void RemoveTempsAndDie(int sig) {
  for (std::atomic<pid_t>& c : g_children)
    if (const pid_t group = c.load(std::memory_order_acquire); group > 0) ::kill(-group, SIGTERM);
  // Other threads run on until the process dies and may create files in a watched directory after
  // this thread emptied it: a forked cleaner (_Fork: async-signal-safe) waits for this process to be
  // gone, then removes the directories once more.
  bool directories = false;
  for (TempSlot& s : g_temps) directories |= s.used.load(std::memory_order_acquire) && s.kind != TempKind::kFile;
  if (directories) {
    const pid_t self = ::getpid();
    if (::_Fork() == 0) {
      while (::getppid() == self) {
        const struct timespec wait {0, 5000000};
        ::nanosleep(&wait, nullptr);
      }
      RemoveTemps();
      // The process's children, ended by the same signal (a terminal's or timeout's to the process
      // group), may still be dying and writing into the directories: again until none is left, for
      // at most two seconds.
      for (int i = 0; i < 100 && TempsLeft(); ++i) {
        const struct timespec wait {0, 20000000};
        ::nanosleep(&wait, nullptr);
        RemoveTemps();
      }
      ::_exit(0);
    }
  }
  RemoveTemps();
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  ::sigaction(sig, &dfl, nullptr);
  ::raise(sig);  // delivered when the handler returns: the process ends as the signal meant
}

// std::exit runs static destructors but not those of the OutputFiles on the stack.
struct RemoveTempsAtExit {
  ~RemoveTempsAtExit() { RemoveTemps(); }
} g_remove_at_exit;

void InstallHandlers() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGABRT}) {
    struct sigaction old {};
    ::sigaction(sig, nullptr, &old);
    if (old.sa_handler != SIG_DFL) continue;  // ignored (nohup) or someone else's: leave it
    struct sigaction sa {};
    sa.sa_handler = RemoveTempsAndDie;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

int RegisterTemp(const std::string& path, TempKind kind = TempKind::kFile) {
  static std::once_flag installed;
  std::call_once(installed, InstallHandlers);
  if (path.size() >= PATH_MAX) return -1;
  const std::lock_guard<std::mutex> lock(g_temps_mutex);
  for (int i = 0; i < kTempSlots; ++i) {
    if (g_temps[i].used.load(std::memory_order_relaxed)) continue;
    std::memcpy(g_temps[i].path, path.c_str(), path.size() + 1);
    g_temps[i].kind = kind;
    g_temps[i].used.store(true, std::memory_order_release);
    return i;
  }
  return -1;  // beyond the slots the file is still removed on every path but a signal
}

void UnregisterTemp(int slot) noexcept {
  if (slot < 0) return;
  const std::lock_guard<std::mutex> lock(g_temps_mutex);
  g_temps[slot].used.store(false, std::memory_order_release);
}

bool WriteAll(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      return false;
    }
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

// The mode a new file gets from the umask, or the mode of the file it replaces.
mode_t ModeFor(const fs::path& target) {
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0) return st.st_mode & 07777;
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return 0666 & ~mask;
}

}  // namespace

OutputFile::OutputFile(const std::string& path, OutputOptions options) : path_(path), options_(std::move(options)) {
  if (path_.empty()) ThrowInput("an empty path: cannot write {}", options_.what);
  if (path_ == "-" && options_.allow_stdout) {
    if (g_stdout_taken.exchange(true)) Fail("standard output already carries another output of this run");
    std::fflush(stdout);
    stdout_fd_ = ::fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
    const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    const bool moved = stdout_fd_ >= 0 && null_fd >= 0 && ::dup2(null_fd, STDOUT_FILENO) >= 0;
    const int err = errno;
    if (null_fd >= 0) ::close(null_fd);
    if (!moved) Fail(std::strerror(err));
    return;
  }
  target_ = path_;
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(target_, ec))) {
    const fs::path resolved = fs::canonical(target_, ec);
    if (ec) {
      const std::string why = ec.message();
      Fail(fmt::format("is a dangling symbolic link to '{}' ({})", fs::read_symlink(target_, ec).string(), why));
    }
    target_ = resolved;
  }
  const fs::file_status st = fs::status(target_, ec);
  if (fs::is_directory(st)) Fail("is a directory");
  if (fs::exists(st) && !fs::is_regular_file(st))
    Fail("is not a regular file (a device, FIFO or socket); outputs are written whole through a temporary file and a rename");
  if (fs::exists(st) && ::access(target_.c_str(), W_OK) != 0) Fail(std::strerror(errno));
  for (const fs::path& input : options_.inputs)
    if (fs::equivalent(target_, input, ec)) Fail(fmt::format("is also an input of this run ('{}')", input.string()));
  const std::string name = target_.filename().string(), ext = target_.extension().string();
  if (name.empty() || name == "." || name == "..") Fail("names a directory, not a file");
  // The extension stays last, for writers that choose the format by the file name.
  std::string tmpl = ((target_.has_parent_path() ? target_.parent_path() : fs::path(".")) /
                      ("." + name.substr(0, 200) + ".tmp-XXXXXX" + (ext.size() <= 16 ? ext : std::string())))
                         .string();
  fd_ = ::mkostemps(tmpl.data(), static_cast<int>(ext.size() <= 16 ? ext.size() : 0), O_CLOEXEC);
  if (fd_ < 0) Fail(std::strerror(errno));
  temp_ = tmpl;
  slot_ = RegisterTemp(tmpl);
  ::fchmod(fd_, ModeFor(target_));
}

OutputFile::OutputFile(OutputFile&& other) noexcept { *this = std::move(other); }

OutputFile& OutputFile::operator=(OutputFile&& other) noexcept {
  if (this == &other) return *this;
  Discard();
  path_ = std::move(other.path_);
  options_ = std::move(other.options_);
  target_ = std::move(other.target_);
  temp_ = std::move(other.temp_);
  fd_ = std::exchange(other.fd_, -1);
  written_ = std::exchange(other.written_, false);
  stdout_fd_ = std::exchange(other.stdout_fd_, -1);
  slot_ = std::exchange(other.slot_, -1);
  other.path_.clear();
  other.temp_.clear();
  return *this;
}

OutputFile::~OutputFile() { Discard(); }

void OutputFile::Discard() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!temp_.empty()) ::unlink(temp_.c_str());
  temp_.clear();
  UnregisterTemp(slot_);
  slot_ = -1;
  if (stdout_fd_ >= 0) ::close(stdout_fd_);
  stdout_fd_ = -1;
}

void OutputFile::Fail(const std::string& reason) {
  Discard();
  ThrowInput("{}: cannot write {}: {}", path_ == "-" ? std::string("- (standard output)") : path_, options_.what, reason);
}

void OutputFile::Write(std::string_view bytes) {
  if (empty()) return;
  if (is_stdout()) {
    if (!WriteAll(stdout_fd_, bytes)) Fail(std::strerror(errno));
    written_ = true;
    return;
  }
  if (fd_ < 0) Fail("written twice");
  if (!WriteAll(fd_, bytes)) Fail(std::strerror(errno));
  Close();
}

void OutputFile::Written() {
  if (empty()) return;
  if (fd_ < 0) Fail("written twice");
  Close();
}

void OutputFile::Close() {
  if (options_.sync && ::fsync(fd_) != 0) Fail(std::strerror(errno));
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) Fail(std::strerror(errno));
  written_ = true;
}

void TestSignalPoint(std::string_view point) {
  static const std::optional<std::pair<std::string, long>> planned = []() -> std::optional<std::pair<std::string, long>> {
    const char* env = std::getenv("RAYSPACE_TEST_SIGTERM");
    if (!env) return std::nullopt;
    const std::string_view spec(env);
    const std::size_t colon = spec.rfind(':');
    if (colon == std::string_view::npos) return std::nullopt;
    char* end = nullptr;
    const std::string count(spec.substr(colon + 1));
    const long n = std::strtol(count.c_str(), &end, 10);
    if (end == count.c_str() || *end != '\0' || n < 1) return std::nullopt;
    return std::make_pair(std::string(spec.substr(0, colon)), n);
  }();
  static std::atomic<long> calls{0};
  if (planned && planned->first == point && calls.fetch_add(1) + 1 == planned->second) ::raise(SIGTERM);
}

void OutputFile::Publish() {
  if (empty() || is_stdout()) return;
  if (!written_ || temp_.empty()) Fail("nothing was written");
  TestSignalPoint("publish");
  if (::rename(temp_.c_str(), target_.c_str()) != 0) Fail(std::strerror(errno));
  temp_.clear();
  UnregisterTemp(slot_);
  slot_ = -1;
}

void PublishAll(const std::vector<OutputFile*>& outputs) {
  for (OutputFile* o : outputs)
    if (o) o->Publish();
}

namespace {
// Two outputs are one file when their (st_dev, st_ino) match (hard links, symbolic links, any
// spelling), or, for a file not there yet, when their absolute, weakly canonical paths do.
struct FileIdentity {
  bool exists = false;
  dev_t dev = 0;
  ino_t ino = 0;
  fs::path path;
  bool operator==(const FileIdentity& o) const {
    return exists == o.exists && (exists ? dev == o.dev && ino == o.ino : path == o.path);
  }
};

FileIdentity IdentityOf(const fs::path& p) {
  FileIdentity id;
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0) {
    id.exists = true;
    id.dev = st.st_dev;
    id.ino = st.st_ino;
    return id;
  }
  std::error_code ec;
  const fs::path abs = fs::absolute(p, ec);
  id.path = fs::weakly_canonical(ec ? p : abs, ec).lexically_normal();
  if (ec) id.path = abs.lexically_normal();
  return id;
}
}  // namespace

void CheckOutputParent(const std::string& dir, std::string_view option) {
  std::error_code ec;
  fs::path p = fs::path(dir).lexically_normal();
  if (!p.has_filename() && p.has_parent_path()) p = p.parent_path();  // "a/b/" -> "a/b"
  const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec))
    ThrowInput("{} {}: the directory {} does not exist; an output directory is created, its parents are not", option, dir,
               parent.string());
}

bool MakeOutputDirectory(const std::string& dir, std::string_view option) {
  std::error_code ec;
  fs::path p = fs::path(dir).lexically_normal();
  if (p.has_filename() == false && p.has_parent_path()) p = p.parent_path();  // "a/b/" -> "a/b"
  const fs::file_status st = fs::status(p, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(st)) ThrowInput("{} {}: not a directory", option, dir);
    return false;
  }
  CheckOutputParent(dir, option);
  fs::create_directory(p, ec);
  if (ec) ThrowInput("{} {}: cannot create the directory ({})", option, dir, ec.message());
  return true;
}

void CheckDistinctOutputs(const std::vector<const OutputFile*>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (!outputs[i] || outputs[i]->empty() || outputs[i]->is_stdout()) continue;
    const FileIdentity a = IdentityOf(outputs[i]->target());
    for (std::size_t j = 0; j < i; ++j) {
      if (!outputs[j] || outputs[j]->empty() || outputs[j]->is_stdout()) continue;
      if (IdentityOf(outputs[j]->target()) == a)
        ThrowInput("{}: given as {} and as {}: each output needs its own file", outputs[i]->path(), outputs[j]->what(),
                   outputs[i]->what());
    }
  }
}

TempDirectory::TempDirectory(const std::filesystem::path& path, bool adopt) : path_(path), adopted_(adopt) {
  std::error_code ec;
  if (adopt) {
    if (!fs::is_directory(path_, ec) || !fs::is_empty(path_, ec))
      ThrowInput("{}: expected an empty directory", path_.string());
  } else if (!fs::create_directory(path_, ec) || ec) {
    ThrowInput("{}: cannot create the directory ({})", path_.string(), ec ? ec.message() : "it exists");
  }
  slot_ = RegisterTemp(fs::absolute(path_, ec).string(), adopt ? TempKind::kContents : TempKind::kDirectory);
}

TempDirectory::~TempDirectory() {
  if (path_.empty()) return;
  UnregisterTemp(slot_);
  std::error_code ec;
  if (!adopted_) {
    fs::remove_all(path_, ec);
    return;
  }
  for (const auto& e : fs::directory_iterator(path_, ec)) fs::remove_all(e.path(), ec);
}

void TempDirectory::Keep() {
  UnregisterTemp(slot_);
  slot_ = -1;
  path_.clear();
}

int RunShellCommand(const std::string& command) {
  static std::once_flag installed;
  std::call_once(installed, InstallHandlers);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);  // a group of its own: the handler ends it whole
  const char* argv[] = {"sh", "-c", command.c_str(), nullptr};
  pid_t pid = -1;
  const int failed = ::posix_spawn(&pid, "/bin/sh", nullptr, &attr, const_cast<char* const*>(argv), environ);
  posix_spawnattr_destroy(&attr);
  if (failed) return -1;
  int slot = -1;
  for (int i = 0; i < kChildSlots && slot < 0; ++i) {
    pid_t free = 0;
    if (g_children[i].compare_exchange_strong(free, pid, std::memory_order_acq_rel)) slot = i;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (slot >= 0) g_children[slot].store(0, std::memory_order_release);
  return status;
}

}  // namespace rayspace
