// Output that cannot be written: a full disk, a file size limit, a folder without write
// permission. Each is an OutputError naming the file with the system's reason (exit code 3
// from the command line), and an atomic write that fails leaves no temporary file behind.
#include <catch2/catch.hpp>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <functional>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/base/error.hpp"
#include "core/io/output.hpp"
#include "core/run/driver.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

std::vector<std::string> files_in(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    names.push_back(entry.path().filename().string());
  return names;
}

std::string output_error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const OutputError& error) {
    return error.what();
  }
  return "no OutputError";
}

// RLIMIT_FSIZE for the scope: a write past the limit fails with EFBIG instead of filling a
// disk. SIGXFSZ, which would kill the process, is ignored meanwhile.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    saved_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, saved_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*saved_handler_)(int) = SIG_DFL;
};

}  // namespace

TEST_CASE("a full disk is an OutputError naming the file and the reason", "[output]") {
  // /dev/full accepts open() and fails every write() with ENOSPC, as a full disk does.
  if (!std::filesystem::exists("/dev/full")) {
    WARN("no /dev/full on this system: skipped");
    return;
  }
  const std::string message = output_error_of([] { write_file_checked("/dev/full", std::string(100000, 'x')); });
  CHECK_THAT(message, Catch::StartsWith("/dev/full: write failed (") && Catch::Contains("No space left on device"));
  // The name the messages give can be another than the one written (the atomic writer's
  // final name instead of its temporary one).
  CHECK_THAT(output_error_of([] { write_file_checked("/dev/full", "x", "run.json"); }),
             Catch::StartsWith("run.json: write failed (No space left on device)"));
}

TEST_CASE("an atomic write that fails midway leaves neither a partial file nor a temporary one", "[output]") {
  const auto dir = fresh_directory("output_file_size_limit");
  write_file_atomically(dir / "series.csv", "old\n");
  {
    const FileSizeLimit limit(4096);
    // A 64 kB frame stops at 4 kB: EFBIG, like ENOSPC a failed write().
    const std::string message =
        output_error_of([&] { write_file_atomically(dir / "series.csv", std::string(65536, 'x')); });
    CHECK_THAT(message, Catch::StartsWith((dir / "series.csv").string() + ": write failed (File too large)"));
  }
  CHECK(files_in(dir) == std::vector<std::string>{"series.csv"});
  CHECK(read_text(dir / "series.csv") == "old\n");  // the previous complete file stays
  // A rename that fails (a folder of that name is in the way) cleans up too.
  std::filesystem::create_directories(dir / "run.json" / "in_the_way");
  CHECK_THAT(output_error_of([&] { write_file_atomically(dir / "run.json", "{}\n"); }),
             Catch::Contains("run.json: cannot rename the finished file into place"));
  CHECK(files_in(dir).size() == 2);  // series.csv and the folder run.json, no run.json.tmp.<pid>
}

TEST_CASE("an unwritable folder is an OutputError (not checked as root - which ignores permissions)", "[output]") {
  const auto dir = fresh_directory("output_unwritable");
  const auto locked = dir / "locked";
  std::filesystem::create_directories(locked);
  std::filesystem::permissions(locked, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec |
                                           std::filesystem::perms::group_read | std::filesystem::perms::group_exec |
                                           std::filesystem::perms::others_read | std::filesystem::perms::others_exec);
  if (::geteuid() == 0) {
    WARN("running as root: permissions are not enforced, the unwritable-folder assertions are skipped");
    return;
  }
  CHECK_THAT(output_error_of([&] { write_file_atomically(locked / "run.json", "{}\n"); }),
             Catch::StartsWith((locked / "run.json").string() + ": cannot write (Permission denied)"));
  CHECK(files_in(locked).empty());
  RunOutput output(locked / "run", FrameFormats{}, {"step"});
  CHECK_THAT(output_error_of([&] { output.prepare(); }),
             Catch::Contains("cannot create the output folder (Permission denied)"));
}

TEST_CASE("output errors through the binary: exit code 3 and one line", "[cli][output]") {
  const auto dir = fresh_directory("cli_output_errors");
  const std::string scene = scene_path("dambreak.json");
  // A file size limit of 4 blocks (2 kB with dash's 512-byte blocks): the probe of
  // series.csv fits, run.json (about 6 kB) or the first frame (18 kB) does not: the disk
  // is "full" after the run has started.
  const auto out = dir / "limited";
  const std::string command = "trap '' XFSZ; ulimit -f 4; " + std::string(MPS_LAB_BINARY) + " run " + scene +
                              " --end-time 0.01 --out " + out.string() + " 2> " + (dir / "err").string();
  const int status = std::system(command.c_str());
  CHECK((WIFEXITED(status) ? WEXITSTATUS(status) : -1) == 3);
  const std::string error = read_text(dir / "err");
  CHECK(std::count(error.begin(), error.end(), '\n') == 1);
  CHECK_THAT(error, Catch::StartsWith("mps_lab: error: " + out.string() + "/") &&
                        Catch::Contains(": write failed (File too large)"));
  for (const auto& name : files_in(out)) CHECK(name.find(".tmp.") == std::string::npos);
  // /dev/full is not a folder: the output folder cannot be made.
  const auto result = run_mps_lab("run " + scene + " --end-time 0.01 --out /dev/full/run", "dev_full");
  CHECK(result.exit_code == 3);
  CHECK_THAT(result.stderr_text, Catch::StartsWith("mps_lab: error: /dev/full/run: cannot create the output folder"));
}

TEST_CASE("a frame that fails on the background writer stops the run with an OutputError naming it", "[output]") {
  const auto dir = fresh_directory("output_background_failure");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.output_directory = dir.string();
  options.overrides = {"time.end_time=0.01"};
  std::string message;
  {
    // 12 kB: run.json at the start (about 6 kB), series.csv and the first CSV frame fit, the
    // first VTK frame (18 kB) does not; it fails on the writer thread, not in write_frame.
    const FileSizeLimit limit(12 * 1024);
    message = output_error_of([&] { run_simulation(options, registries().methods, registries().walls); });
  }
  CHECK(message == (dir / "output_000000.vtk").string() + ": write failed (File too large)");
  CHECK_FALSE(std::filesystem::exists(dir / "output_000000.vtk"));
  for (const auto& name : files_in(dir)) CHECK(name.find(".tmp.") == std::string::npos);
  CHECK(nlohmann::json::parse(read_text(dir / "run.json"))["status"] == "running");  // never finalised
}
