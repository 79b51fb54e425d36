// The files a user names for rayspace's outputs (images, statistics, reports, saved inputs). Each is
// checked before the work that fills it, so that a bad path costs no render; it is written whole to
// a temporary file beside it and renamed into place only when every write, the sync and the close
// succeeded, so that a failed or interrupted run leaves the old file or none, never a truncated one.
// SIGINT, SIGTERM, SIGHUP and SIGABRT remove the temporary files before the process dies.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace rayspace {

struct OutputOptions {
  std::string what;                            // what the file holds, for messages: "the statistics file"
  bool allow_stdout = false;                   // "-" names standard output
  bool sync = true;                            // fsync before the rename (off for bulk files such as saved inputs)
  std::vector<std::filesystem::path> inputs;   // files the run reads, which the output must not replace
};

class OutputFile {
 public:
  OutputFile() = default;  // no output: Commit does nothing
  // Checks `path` and creates the temporary file beside it. Throws InputError naming `path` when it is
  // a directory, a device, FIFO or socket, a dangling symbolic link, a read-only file, one of
  // options.inputs, or in a directory where no file can be created. "-" with allow_stdout takes
  // standard output for this file alone: from here on, what the program would print there (a summary)
  // is dropped, so that a reader of standard output gets the file's bytes unmixed; errors, verdicts
  // and warnings go to standard error as always.
  OutputFile(const std::string& path, OutputOptions options);
  OutputFile(OutputFile&& other) noexcept;
  OutputFile& operator=(OutputFile&& other) noexcept;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();  // removes the temporary file unless committed

  bool empty() const { return path_.empty(); }
  bool is_stdout() const { return stdout_fd_ >= 0; }
  const std::string& path() const { return path_; }  // as the user gave it
  const std::string& what() const { return options_.what; }
  // The file a symbolic link names, or the path itself: where the output lands.
  const std::filesystem::path& target() const { return target_; }
  // Where a writer that needs a file name writes before CommitWritten (not for standard output).
  const std::filesystem::path& temp_path() const { return temp_; }

  // Writes `bytes` as the whole file: into the temporary file, synced and closed, or to standard
  // output. Throws InputError naming the path when a write, the sync or the close fails; the temporary
  // file is gone then.
  void Write(std::string_view bytes);
  // The temporary file was written through temp_path(): syncs and closes it.
  void Written();
  // Renames the written temporary file into place. A run with several outputs writes them all first
  // and publishes them together, so that a failed write leaves none of them behind.
  void Publish();
  // Write, then Publish.
  void Commit(std::string_view bytes) {
    Write(bytes);
    Publish();
  }

 private:
  [[noreturn]] void Fail(const std::string& reason);
  void Discard() noexcept;
  void Close();
  std::string path_;
  OutputOptions options_;
  std::filesystem::path target_, temp_;
  int fd_ = -1;         // the temporary file, open until written
  bool written_ = false;
  int stdout_fd_ = -1;  // "-": the original standard output
  int slot_ = -1;       // the temporary file's entry in the signal handler's list
};

// An output directory given as `option` (e.g. "--save-inputs"): creates `dir` itself if it is missing,
// never its parents. Throws InputError naming the option when the parent directory does not exist,
// `dir` is not a directory, or it cannot be created. Returns whether it was created here.
bool MakeOutputDirectory(const std::string& dir, std::string_view option);
// The part of MakeOutputDirectory that creates nothing: the parent of `dir` must exist.
void CheckOutputParent(const std::string& dir, std::string_view option);

// A directory that holds something only while it is being filled: removed with everything in it
// (or, adopted, emptied) when the object goes, at exit, and by SIGINT, SIGTERM, SIGHUP and SIGABRT
// (async-signal-safe), unless Keep was called. A run's scratch directory under $TMPDIR, or an output
// directory that must not be left half-written (diff --save-inputs).
class TempDirectory {
 public:
  // Creates `path` (its parent must exist), or with `adopt` takes the empty directory there, which is
  // emptied rather than removed. Throws InputError naming it when it cannot.
  explicit TempDirectory(const std::filesystem::path& path, bool adopt = false);
  ~TempDirectory();
  TempDirectory(const TempDirectory&) = delete;
  TempDirectory& operator=(const TempDirectory&) = delete;
  const std::filesystem::path& path() const { return path_; }
  // The directory is complete: it stays, and is no longer watched.
  void Keep();

 private:
  std::filesystem::path path_;
  bool adopted_ = false;
  int slot_ = -1;
};

// Throws InputError when two of `outputs` would land in the same file.
void CheckDistinctOutputs(const std::vector<const OutputFile*>& outputs);
// Publishes every written output of `outputs`.
void PublishAll(const std::vector<OutputFile*>& outputs);

// Test use: with RAYSPACE_TEST_SIGTERM=POINT:N in the environment, the N-th call (counted over the
// process, 1-based) of TestSignalPoint(POINT) raises SIGTERM in the calling thread, so that a test
// interrupts a run at a known moment mid-write instead of at a time that races it. Points:
// "publish" (an output file written, before its rename into place) and "export.file" (a file of
// an export written into its partial directory). Without the variable it does nothing.
void TestSignalPoint(std::string_view point);

// Runs `command` with /bin/sh -c in a process group of its own and waits for it; returns its wait
// status as std::system does (-1 when it cannot start). A signal that removes the temporaries
// (SIGINT, SIGTERM, SIGHUP, SIGABRT) first sends SIGTERM to every such group still running, so that
// no command outlives the run and writes into its scratch directory.
int RunShellCommand(const std::string& command);

}  // namespace rayspace
