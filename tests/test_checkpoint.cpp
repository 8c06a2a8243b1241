// Checkpoint and restart: the binary format reads back bit for bit and rejects damaged files;
// a run interrupted and resumed writes exactly the files of an uninterrupted run (each
// method, the spec's dam break); SIGTERM stops the real binary cleanly (exit 143).
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <set>
#include <thread>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include "core/base/error.hpp"
#include "core/io/checkpoint.hpp"
#include "core/io/output.hpp"
#include "core/run/driver.hpp"
#include "lab/compare.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;
using namespace std::string_literals;
namespace fs = std::filesystem;

extern char** environ;

namespace {

std::uint64_t bits_of(double value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

std::string checkpoint_error(const std::string& content, const std::string& revision = "rev-a") {
  try {
    CheckpointReader reader(content, "run/checkpoint.bin", revision);
    reader.begin_section("values");
    for (int k = 0; k < 3; ++k) reader.read_double();
    reader.end_section();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// The spec's dam break to `end_time` with `method` into `folder`; stops after `stop_after_steps`
// steps when > 0.
RunResult run_dambreak(const std::string& method, const fs::path& folder, double end_time,
                       long long stop_after_steps = 0, long long checkpoint_every = 0,
                       const std::vector<std::string>& overrides = {}) {
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.method = method;
  options.overrides = overrides;
  options.output_directory = folder.string();
  options.end_time = end_time;
  options.checkpoint_every_steps = checkpoint_every;
  auto polls = std::make_shared<long long>(0);
  if (stop_after_steps > 0) {
    options.stop_reason = [polls, stop_after_steps] { return ++*polls >= stop_after_steps ? "a test" : ""; };
  }
  return run_simulation(options, registries().methods, registries().walls);
}

RunResult resume(const fs::path& folder, std::optional<double> end_time = std::nullopt) {
  RunOptions options;
  options.resume_directory = folder;
  options.end_time = end_time;
  return run_simulation(options, registries().methods, registries().walls);
}

// The folders hold the same frames, index and series rows, and run.json the same totals.
void require_same_run(const fs::path& uninterrupted, const fs::path& resumed) {
  const auto expected = run_folder_files(uninterrupted);
  const auto actual = run_folder_files(resumed);
  std::set<std::string> expected_names, actual_names;
  for (const auto& file : expected) expected_names.insert(file.first);
  for (const auto& file : actual) actual_names.insert(file.first);
  REQUIRE(actual_names == expected_names);
  for (const auto& [name, content] : expected) {
    INFO(name);
    CHECK(actual.at(name) == content);  // byte for byte
  }
  CHECK(series_rows_without_wall_seconds(resumed) == series_rows_without_wall_seconds(uninterrupted));
  const auto a = nlohmann::json::parse(read_text(uninterrupted / "run.json"));
  const auto b = nlohmann::json::parse(read_text(resumed / "run.json"));
  for (const char* key :
       {"status", "steps", "simulated_time", "frames", "particles", "solver", "method_summary", "stability"}) {
    INFO(key);
    CHECK(b.value(key, nlohmann::json()) == a.value(key, nlohmann::json()));
  }
}

}  // namespace

TEST_CASE("checkpoint format: values read back bit for bit - damaged files are one-line errors", "[checkpoint]") {
  const std::vector<double> doubles = {0.1,
                                       -0.0,
                                       M_PI,
                                       std::numeric_limits<double>::denorm_min(),
                                       std::numeric_limits<double>::max(),
                                       std::numeric_limits<double>::infinity(),
                                       std::numeric_limits<double>::quiet_NaN(),
                                       1.0 / 3.0};
  NeighbourList neighbours;
  neighbours.offsets = {0, 2, 3};
  neighbours.indices = {1, 7, 4};
  neighbours.radius = 0.0525;

  CheckpointWriter writer;
  writer.begin_section("values");
  for (int k = 0; k < 3; ++k) writer.write_double(doubles[static_cast<std::size_t>(k)]);
  writer.end_section();
  writer.begin_section("everything");
  writer.write_doubles(doubles);
  writer.write_vec2s({Vec2(0.1, -0.2), Vec2(1e-300, 3.0)});
  writer.write_int(-1234567890123LL);
  writer.write_size(42);
  writer.write_bool(true);
  writer.write_string("a name, with \n and \0 inside"s);
  writer.write_u8s({0, 1, 255});
  writer.write_chars({'a', 0});
  write_neighbour_list(writer, neighbours);
  writer.end_section();
  const std::string content = writer.file_content("rev-a");

  CheckpointReader reader(content, "run/checkpoint.bin", "rev-a");
  CHECK(reader.revision() == "rev-a");
  CHECK_FALSE(reader.has_section("missing"));
  reader.begin_section("everything");
  const auto read_back = reader.read_doubles();
  REQUIRE(read_back.size() == doubles.size());
  for (std::size_t k = 0; k < doubles.size(); ++k) CHECK(bits_of(read_back[k]) == bits_of(doubles[k]));
  const auto vectors = reader.read_vec2s();
  REQUIRE(vectors.size() == 2);
  CHECK(bits_of(vectors[1].x()) == bits_of(1e-300));
  CHECK(bits_of(vectors[0].y()) == bits_of(-0.2));
  CHECK(reader.read_int() == -1234567890123LL);
  CHECK(reader.read_size() == 42);
  CHECK(reader.read_bool());
  CHECK(reader.read_string() == "a name, with \n and \0 inside"s);
  CHECK(reader.read_u8s() == std::vector<std::uint8_t>{0, 1, 255});
  CHECK(reader.read_chars() == std::vector<char>{'a', 0});
  NeighbourList list;
  read_neighbour_list(reader, list);
  CHECK(list.offsets == neighbours.offsets);
  CHECK(list.indices == neighbours.indices);
  CHECK(bits_of(list.radius) == bits_of(0.0525));
  reader.end_section();

  // Sections are found by name, in any order.
  CheckpointReader again(content, "run/checkpoint.bin", "rev-a");
  again.begin_section("values");
  CHECK(bits_of(again.read_double()) == bits_of(0.1));

  // Damage of every kind is an InputError of one line naming the file.
  CHECK(checkpoint_error(content).empty());
  for (const std::size_t size :
       {content.size() - 1, content.size() / 2, std::size_t{20}, std::size_t{3}, std::size_t{0}}) {
    INFO("truncated to " << size << " bytes");
    const std::string error = checkpoint_error(content.substr(0, size));
    CHECK_THAT(error, Catch::StartsWith("run/checkpoint.bin: ") &&
                          (Catch::Contains("truncated") || Catch::Contains("not an mps_lab checkpoint")));
    CHECK(error.find('\n') == std::string::npos);
  }
  std::string flipped = content;
  flipped[content.size() / 2] = static_cast<char>(flipped[content.size() / 2] ^ 0x10);
  CHECK_THAT(checkpoint_error(flipped), Catch::Contains("run/checkpoint.bin: truncated or corrupted checkpoint"));
  CHECK_THAT(checkpoint_error("PK\x03\x04 a zip file, not a checkpoint"),
             Catch::Contains("run/checkpoint.bin: not an mps_lab checkpoint"));
  CHECK_THAT(checkpoint_error(content, "rev-b"),
             Catch::Contains("run/checkpoint.bin: written by mps_lab rev-a, this is rev-b"));

  CheckpointReader partial(content, "run/checkpoint.bin", "rev-a");
  CHECK_THROWS_WITH(partial.begin_section("stability"), Catch::Contains("run/checkpoint.bin: no section 'stability'"));
  partial.begin_section("values");
  partial.read_double();
  CHECK_THROWS_WITH(partial.end_section(),
                    Catch::Contains("run/checkpoint.bin: section 'values': 16 bytes left unread"));
  partial.read_double();
  partial.read_double();
  CHECK_THROWS_WITH(partial.read_double(), Catch::Contains("run/checkpoint.bin: section 'values': ends early"));

  // A truncated file on disk, as `resume` reads it.
  const auto folder = fresh_directory("checkpoint_truncated");
  write_text(folder / "checkpoint.bin", content.substr(0, content.size() - 9));
  CHECK_THROWS_WITH(CheckpointReader::from_file(folder / "checkpoint.bin", "rev-a"),
                    Catch::Contains((folder / "checkpoint.bin").string() + ": truncated or corrupted checkpoint"));
}

TEST_CASE("interrupted and resumed = uninterrupted - bit for bit: isph with its CFL rule", "[checkpoint]") {
  // Every method with its defaults is resumed bit for bit by the contract suite
  // (tests/test_contract.cpp); this case adds isph's optional CFL rule, whose clock is part of
  // its checkpoint. Stop steps away from the frame (0.05 s) and series (0.005 s) schedules, so
  // that the interruption frame is extra and must be removed by resume; 0.3 s is about 150
  // CFL steps.
  struct Case {
    std::string method;
    long long stop_after;
    std::vector<std::string> overrides;
    std::string tag;
  };
  const std::vector<Case> cases = {Case{"isph", 97, {"methods.isph.time_step_rule=\"cfl\""}, "_cfl"}};
  for (const Case& test : cases) {
    if (registries().methods.find(test.method) == nullptr) continue;  // not built
    INFO("method " << test.method << test.tag);
    const auto uninterrupted = fresh_directory("resume_full_" + test.method + test.tag);
    const auto interrupted = fresh_directory("resume_part_" + test.method + test.tag);
    const RunResult full = run_dambreak(test.method, uninterrupted, 0.3, 0, 0, test.overrides);
    REQUIRE(full.status == "completed");

    const RunResult stopped = run_dambreak(test.method, interrupted, 0.3, test.stop_after, 0, test.overrides);
    CHECK(stopped.status == "interrupted");
    CHECK(stopped.steps == test.stop_after);
    CHECK_THAT(stopped.message, Catch::StartsWith("stopped by a test at t = ") &&
                                    Catch::Contains("mps_lab resume " + interrupted.string()));
    const auto summary = nlohmann::json::parse(read_text(interrupted / "run.json"));
    CHECK(summary["status"] == "interrupted");
    CHECK(summary["checkpoint"]["step"] == test.stop_after);
    CHECK(fs::exists(interrupted / (frame_stem(test.stop_after) + ".vtk")));  // where it stopped

    const RunResult resumed = resume(interrupted);
    CHECK(resumed.status == "completed");
    CHECK(resumed.steps == full.steps);
    CHECK(resumed.simulated_time == full.simulated_time);  // the Kahan clock is restored exactly
    const auto after = nlohmann::json::parse(read_text(interrupted / "run.json"));
    REQUIRE(after["resumed"].size() == 1);
    CHECK(after["resumed"][0]["from_step"] == test.stop_after);
    CHECK(after["resumed"][0]["previous_status"] == "interrupted");
    require_same_run(uninterrupted, interrupted);
  }
}

TEST_CASE("interrupted and resumed = uninterrupted - bit for bit: a reused AMG hierarchy (mps, isph)", "[checkpoint]") {
  // At l0 = 0.0125 m (741 fluid particles) both projection methods solve with AMG and reuse its
  // hierarchy for several steps (amg_reuse_budget, core/linalg/projection_solver.hpp): the
  // interruption falls between two set-ups, so the resumed run must carry the hierarchy, its
  // rows by particle (moved by the cell order every 50 steps) and the reuse budget spent.
  for (const std::string method : {"mps", "isph"}) {
    if (registries().methods.find(method) == nullptr) continue;  // not built
    INFO("method " << method);
    const std::vector<std::string> overrides = {"particle_spacing=0.0125",
                                                "methods." + method + ".preconditioner=\"amg\"",
                                                "methods." + method + ".amg_reuse_budget=8"};
    const auto uninterrupted = fresh_directory("resume_full_amg_" + method);
    const auto interrupted = fresh_directory("resume_part_amg_" + method);
    const RunResult full = run_dambreak(method, uninterrupted, 0.1, 0, 0, overrides);
    REQUIRE(full.status == "completed");
    const auto summary = nlohmann::json::parse(read_text(uninterrupted / "run.json"));
    const auto& solver = summary["method_summary"];
    CHECK(solver["preconditioner"] == "amg");
    CHECK(solver["amg_reused_solves"].get<long long>() > solver["preconditioner_setups"].get<long long>());

    const RunResult stopped = run_dambreak(method, interrupted, 0.1, 123, 0, overrides);
    CHECK(stopped.status == "interrupted");
    const RunResult resumed = resume(interrupted);
    CHECK(resumed.status == "completed");
    require_same_run(uninterrupted, interrupted);
  }
}

TEST_CASE("resume after a hard kill: from the last periodic checkpoint - stale files removed", "[checkpoint]") {
  const auto uninterrupted = fresh_directory("resume_kill_full");
  const auto killed = fresh_directory("resume_kill_part");
  REQUIRE(run_dambreak("mps", uninterrupted, 0.3).status == "completed");
  // A run checkpointing every 100 steps; its checkpoint of step 200 is kept aside at step 250,
  // and put back after the run as if the process had been killed at step 250.
  const auto saved = killed.parent_path() / "mps_lab_test_resume_kill_checkpoint.bin";
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.method = "mps";
  options.output_directory = killed.string();
  options.end_time = 0.3;
  options.checkpoint_every_steps = 100;
  long long polls = 0;
  options.stop_reason = [&] {
    if (++polls == 250) fs::copy_file(killed / "checkpoint.bin", saved, fs::copy_options::overwrite_existing);
    return std::string();
  };
  REQUIRE(run_simulation(options, registries().methods, registries().walls).status == "completed");
  fs::copy_file(saved, killed / "checkpoint.bin", fs::copy_options::overwrite_existing);
  auto summary = nlohmann::json::parse(read_text(killed / "run.json"));
  summary["status"] = "running";
  write_text(killed / "run.json", summary.dump());
  write_text(killed / "output_000250.csv", "a frame the checkpoint does not list\n");
  write_text(killed / "series.csv.tmp.12345", "half a file\n");

  const RunResult resumed = resume(killed);
  CHECK(resumed.status == "completed");
  CHECK_FALSE(fs::exists(killed / "output_000250.csv"));
  CHECK_FALSE(fs::exists(killed / "series.csv.tmp.12345"));
  CHECK(nlohmann::json::parse(read_text(killed / "run.json"))["resumed"][0]["from_step"] == 200);
  require_same_run(uninterrupted, killed);
}

TEST_CASE("resume of a completed run: an error without a later end time - an extension with one", "[checkpoint]") {
  const auto folder = fresh_directory("resume_completed");
  const auto longer = fresh_directory("resume_completed_longer");
  REQUIRE(run_dambreak("mps", folder, 0.1, 0, 100).status == "completed");
  CHECK_THROWS_WITH(resume(folder),
                    Catch::Contains((folder / "run.json").string() +
                                    ": status: the run is complete (t = 0.1 s); give a later --end-time"));
  CHECK_THROWS_AS(resume(folder, 0.1), InputError);
  // Extended to 0.15 s, the run equals one that ran to 0.15 s at once (fixed dt: the same steps).
  const RunResult extended = resume(folder, 0.15);
  CHECK(extended.status == "completed");
  CHECK(extended.steps == 300);
  REQUIRE(run_dambreak("mps", longer, 0.15).status == "completed");
  require_same_run(longer, folder);

  const auto empty = fresh_directory("resume_nothing");
  CHECK_THROWS_WITH(resume(empty), Catch::Contains((empty / "run.json").string() + ": cannot open the run summary"));
}

#ifdef MPS_LAB_WITH_ISPH  // the comparison of mps and isph
TEST_CASE("compare stops after the interrupted method and its run can then be resumed", "[checkpoint]") {
  const auto folder = fresh_directory("compare_interrupted");
  CompareOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.methods = {"mps", "isph"};
  options.output_directory = folder;
  options.end_time = 0.05;
  long long polls = 0;
  options.stop_reason = [&polls] { return ++polls == 40 ? "a test" : ""; };
  const auto rows = compare_methods(options, registries().methods, registries().walls);
  REQUIRE(rows.size() == 1);  // isph was not run
  CHECK(rows[0].status == "interrupted");
  CHECK(rows[0].steps == 40);
  CHECK_FALSE(fs::exists(folder / "isph"));
  CHECK(fs::exists(folder / "mps" / "checkpoint.bin"));
  const RunResult resumed = resume(folder / "mps");
  CHECK(resumed.status == "completed");
  CHECK(resumed.steps == 100);
}
#endif

TEST_CASE("SIGTERM: the binary finishes the step - checkpoints and exits 143 - then resume completes the run",
          "[cli]") {
  const auto uninterrupted = fresh_directory("sigterm_uninterrupted");
  const auto folder = fresh_directory("sigterm_interrupted");
  const std::string scene = scene_path("dambreak.json");
  const auto full = run_mps_lab("run -q --method=mps " + scene + " --out " + uninterrupted.string() + " --end-time 0.5",
                                "sigterm_full");
  REQUIRE(full.exit_code == 0);

  // The same run, started in the background, checkpointing every 50 of its 1000 steps.
  const std::string out = (folder / "stdout").string(), err = (folder / "stderr").string();
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&files, STDERR_FILENO, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const auto run_folder = folder / "run";
  std::vector<std::string> arguments = {
      MPS_LAB_BINARY, "run", "--method=mps",       scene, "--out", run_folder.string(),
      "--end-time",   "0.5", "--checkpoint-every", "50"};
  std::vector<char*> argv;
  for (auto& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  pid_t child = 0;
  REQUIRE(posix_spawn(&child, MPS_LAB_BINARY, &files, nullptr, argv.data(), environ) == 0);
  posix_spawn_file_actions_destroy(&files);

  // SIGTERM once run.json says it is running with a checkpoint of step >= 100 (run.json is
  // written atomically, so it is always complete).
  long long checkpoint_step = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (checkpoint_step < 100 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!fs::exists(run_folder / "run.json")) continue;
    const auto summary = nlohmann::json::parse(read_text(run_folder / "run.json"));
    if (summary["status"] != "running") break;
    if (summary.contains("checkpoint")) checkpoint_step = summary["checkpoint"]["step"];
  }
  REQUIRE(checkpoint_step >= 100);
  // A little later, so that the stop usually falls between frame steps (the run makes about
  // two steps per millisecond on one thread; any step is right).
  std::this_thread::sleep_for(std::chrono::milliseconds(7));
  REQUIRE(::kill(child, SIGTERM) == 0);
  int status = 0;
  REQUIRE(::waitpid(child, &status, 0) == child);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 143);  // 128 + SIGTERM
  CHECK_THAT(read_text(err), Catch::Contains("stopped by SIGTERM") && Catch::Contains("mps_lab resume"));

  const auto summary = nlohmann::json::parse(read_text(run_folder / "run.json"));
  CHECK(summary["status"] == "interrupted");
  CHECK_THAT(summary["message"].get<std::string>(), Catch::StartsWith("stopped by SIGTERM at t = "));
  const long long stopped_at = summary["steps"];
  CHECK(stopped_at >= 100);
  CHECK(stopped_at < 1000);
  CHECK(summary["checkpoint"]["step"] == stopped_at);
  CHECK(fs::exists(run_folder / "checkpoint.bin"));
  CHECK(fs::exists(run_folder / (frame_stem(stopped_at) + ".csv")));  // the final frame
  for (const auto& entry : fs::directory_iterator(run_folder)) {      // no temporary or partial files
    const std::string name = entry.path().filename().string();
    INFO(name);
    CHECK(name.find(".tmp") == std::string::npos);
  }

  const auto resumed = run_mps_lab("resume -q " + run_folder.string(), "sigterm_resume");
  CHECK(resumed.exit_code == 0);
  CHECK(resumed.stderr_text.empty());
  CHECK(nlohmann::json::parse(read_text(run_folder / "run.json"))["status"] == "completed");
  CHECK(read_text(run_folder / "output_001000.csv") == read_text(uninterrupted / "output_001000.csv"));
  CHECK(read_text(run_folder / "output_001000.vtk") == read_text(uninterrupted / "output_001000.vtk"));
  require_same_run(uninterrupted, run_folder);

  // Resuming the completed run again says so: exit 2, one line.
  const auto again = run_mps_lab("resume " + run_folder.string(), "sigterm_again");
  CHECK(again.exit_code == 2);
  CHECK_THAT(again.stderr_text, Catch::StartsWith("mps_lab: error: ") && Catch::Contains("the run is complete") &&
                                    Catch::EndsWith("--end-time to continue it\n"));
}
