// The command line: listing, a run, and bad input giving one line and a non-zero exit.
#include <catch2/catch.hpp>

#include <sstream>

#include <unistd.h>

#include <algorithm>
#include <stdexcept>

#include "core/run/driver.hpp"
#include "core/run/method.hpp"
#include "support.hpp"

using namespace mps_lab::testing;

namespace {

std::size_t line_count(const std::string& text) {
  std::size_t lines = 0;
  for (char c : text) lines += c == '\n';
  return lines;
}

}  // namespace

TEST_CASE("mps_lab methods lists each method on one line", "[cli]") {
  const auto result = run_mps_lab("methods", "methods");
  CHECK(result.exit_code == 0);
  // One line per registered method: its name, then its description.
  std::istringstream lines(result.stdout_text);
  std::string line;
  for (const auto* method : registries().methods.all()) {
    REQUIRE(std::getline(lines, line));
    CHECK_THAT(line, Catch::StartsWith(method->name + " ") && Catch::EndsWith(method->description));
  }
  CHECK(line_count(result.stdout_text) == registries().methods.all().size());
}

TEST_CASE("mps_lab --version names the version and the git revision of the build", "[cli]") {
  const auto result = run_mps_lab("--version", "version");
  CHECK(result.exit_code == 0);
  CHECK(result.stdout_text == std::string("mps_lab ") + MPS_LAB_VERSION + " (git " + mps_lab::git_revision() + ")\n");
}

TEST_CASE("mps_lab run with --out - --set and --end-time", "[cli]") {
  const auto out = fresh_directory("cli_run_out");
  const auto result = run_mps_lab("run --method=mps " + scene_path("dambreak.json") + " --out " + out.string() +
                                      " --set methods.mps.relaxation=0.25 --end-time 0.05",
                                  "run");
  CHECK(result.exit_code == 0);
  CHECK(result.stderr_text.empty());  // no progress line when stderr is not a terminal
  const auto summary = nlohmann::json::parse(read_text(out / "run.json"));
  CHECK(summary["steps"] == 100);
  CHECK(summary["parameters"]["relaxation"] == 0.25);
  CHECK(std::filesystem::exists(out / "output_000100.vtk"));
}

// The parameter of `method` called `name`.
const mps_lab::ParameterSpec& parameter_spec(const mps_lab::MethodInfo& method, const std::string& name) {
  for (const auto& spec : method.parameters) {
    if (spec.name == name) return spec;
  }
  FAIL("methods." << method.name << "." << name << " is not a declared parameter");
  throw std::logic_error("unreachable");
}

TEST_CASE("mps_lab compare and run --load-setting: each method's load setting, then the --set overrides", "[cli]") {
  // compare --load-setting runs every method with its declared setting for wall loads
  // (MethodInfo::load_setting): run.json records the assignments first among the overrides, and
  // the parameters hold the values.
  const auto out = fresh_directory("cli_compare_load_setting");
  const auto compared = run_mps_lab("compare " + scene_path("hydrostatic.json") + " --load-setting --no-analysis -q" +
                                        " --end-time 0.002 --out " + out.string(),
                                    "compare_load_setting");
  REQUIRE(compared.exit_code == 0);
  for (const auto* method : registries().methods.all()) {
    INFO("method " << method->name);
    const auto summary = nlohmann::json::parse(read_text(out / method->name / "run.json"));
    const std::vector<std::string> expected = mps_lab::load_setting_overrides(*method);
    const auto overrides = summary["overrides"].get<std::vector<std::string>>();
    REQUIRE(overrides.size() >= expected.size());
    CHECK(std::equal(expected.begin(), expected.end(), overrides.begin()));
    for (const auto& [name, value] : method->load_setting.parameters) {
      CHECK(summary["parameters"][name] == nlohmann::json::parse(value));
    }
  }
  // run --load-setting with a --set of the same parameter back to its default: the --set wins.
  for (const auto* method : registries().methods.all()) {
    if (method->load_setting.parameters.empty()) continue;
    const std::string name = method->load_setting.parameters.front().first;
    const nlohmann::json default_value = parameter_spec(*method, name).default_value;
    const auto run_out = fresh_directory("cli_run_load_setting_" + method->name);
    const auto ran = run_mps_lab("run --method=" + method->name + " " + scene_path("hydrostatic.json") +
                                     " --load-setting --end-time 0.002 -q --out " + run_out.string() +
                                     " --set 'methods." + method->name + "." + name + "=" + default_value.dump() + "'",
                                 "run_load_setting_" + method->name);
    REQUIRE(ran.exit_code == 0);
    const auto summary = nlohmann::json::parse(read_text(run_out / "run.json"));
    CHECK(summary["parameters"][name] == default_value);
  }
}

TEST_CASE("run.json records how waiting OpenMP threads wait - the runtime's own settings", "[cli][threads]") {
  // core/run/thread_governor.cpp: GOMP_SPINCOUNT and OMP_WAIT_POLICY as the run found them.
  const auto ran = [](const std::string& environment, const std::string& tag) {
    const auto out = fresh_directory("cli_spin_" + tag);
    const std::string command = "env -u GOMP_SPINCOUNT -u OMP_WAIT_POLICY " + environment + " " +
                                std::string(MPS_LAB_BINARY) + " run --method=mps " + scene_path("dambreak.json") +
                                " --quiet --end-time 0.005 --out " + out.string() + " > /dev/null 2>&1";
    REQUIRE(std::system(command.c_str()) == 0);
    return nlohmann::json::parse(read_text(out / "run.json"))["threads_used"];
  };
  const auto unset = ran("", "default");
  CHECK(unset["gomp_spincount"] == "libgomp default");
  CHECK(unset["omp_wait_policy"] == "unset");
  const auto chosen = ran("GOMP_SPINCOUNT=10000", "chosen");
  CHECK(chosen["gomp_spincount"] == "10000");
  const auto passive = ran("OMP_WAIT_POLICY=PASSIVE", "passive");
  CHECK(passive["omp_wait_policy"] == "PASSIVE");
}

TEST_CASE("mps_lab run's summary line names the team that ran the steps", "[cli][threads]") {
  // The line read "(2 threads)", the threads available, even when --threads 1 ran every step on
  // one (2026-11-29). It now names the teams of run.json's threads_used.steps_by_team.
  for (const int threads : {1, 2}) {
    const auto out = fresh_directory("cli_team_" + std::to_string(threads));
    const auto result = run_mps_lab("run --method=mps " + scene_path("dambreak.json") + " --end-time 0.01 --threads " +
                                        std::to_string(threads) + " --out " + out.string(),
                                    "team_" + std::to_string(threads));
    REQUIRE(result.exit_code == 0);
    const auto used = nlohmann::json::parse(read_text(out / "run.json"))["threads_used"];
    CHECK(used["steps_by_team"][std::to_string(threads)] == 20);
    const std::string expected = threads == 1 ? "(1 thread)" : "(2 threads)";
    INFO(result.stdout_text);
    CHECK(result.stdout_text.find(expected) != std::string::npos);
  }
}

TEST_CASE("bad input: one line naming the problem - non-zero exit - nothing run", "[cli][input]") {
  const auto dir = fresh_directory("cli_bad_input");
  write_text(dir / "truncated.json", R"({"domain": {"min": [0, 0], "max": [1, 0.6]}, "fluid_bl)");
  write_text(dir / "unknown_key.json", R"({"domain": {"min": [0, 0], "max": [1, 0.6]},
    "fluid_blocks": [{"min": [0, 0], "max": [0.25, 0.5]}], "physics": {"viscosity": 1e-6}})");
  struct Case {
    std::string arguments, expected;
    int exit_code;
  };
  const std::vector<Case> cases = {
      {"run " + (dir / "truncated.json").string(), "truncated.json: not valid JSON", 2},
      {"run " + (dir / "unknown_key.json").string(), "unknown_key.json: physics.viscosity: unknown key", 2},
      {"run " + (dir / "missing.json").string(), "missing.json: cannot open the scene file", 2},
      {"run --method=sph " + scene_path("dambreak.json"), "--method: sph: unknown method (registered: ", 2},
      {"run " + scene_path("dambreak.json") + " --set time.time_step=-1",
       "time.time_step: got -1, expected a number > 0", 2},
      {"run " + scene_path("dambreak.json") + " --set nonsense", "--set: nonsense: expected key=value", 2},
      {"run " + scene_path("dambreak.json") + " --out /proc/mps_lab_cannot_write",
       "/proc/mps_lab_cannot_write: cannot create the output folder", 3},
  };
  for (const auto& test : cases) {
    INFO(test.arguments);
    const auto result = run_mps_lab(test.arguments, "bad");
    CHECK(result.exit_code == test.exit_code);
    CHECK(line_count(result.stderr_text) == 1);
    CHECK_THAT(result.stderr_text, Catch::StartsWith("mps_lab: error: ") && Catch::Contains(test.expected));
  }
  // A read-only folder (when not running as root, which ignores permissions).
  const auto read_only = dir / "read_only";
  std::filesystem::create_directories(read_only);
  std::filesystem::permissions(read_only, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  if (::geteuid() != 0) {
    const auto result = run_mps_lab("run " + scene_path("dambreak.json") + " --out " + read_only.string(), "ro");
    CHECK(result.exit_code == 3);
    CHECK_THAT(result.stderr_text, Catch::Contains("not writable"));
  }
  // An existing file where the folder should be.
  write_text(dir / "a_file", "x");
  const auto result = run_mps_lab("run " + scene_path("dambreak.json") + " --out " + (dir / "a_file").string(), "file");
  CHECK(result.exit_code == 3);
  CHECK(line_count(result.stderr_text) == 1);
}

TEST_CASE("a run whose solver fails: status solver_failed in run.json - one line - exit 1 - the state kept", "[cli]") {
  const auto out = fresh_directory("cli_failed_run");
  // A CG capped at one iteration cannot reach 1e-8; asked to stop on it, the run ends in step 1.
  const auto result = run_mps_lab("run " + scene_path("dambreak.json") + " --out " + out.string() +
                                      " --set methods.mps.cg_max_iterations=1 --set stability.on_solver_failure=stop",
                                  "failed_run");
  CHECK(result.exit_code == 1);
  CHECK(line_count(result.stderr_text) == 1);
  CHECK_THAT(result.stderr_text, Catch::Contains("solver_failed") && Catch::Contains("step 1") &&
                                     Catch::Contains("cg_tolerance 1e-08 after 1 iterations"));
  const auto summary = nlohmann::json::parse(read_text(out / "run.json"));
  CHECK(summary["status"] == "solver_failed");
  CHECK(summary["stability"]["counts"]["solver"] == 1);
  CHECK_THAT(summary["message"].get<std::string>(), Catch::StartsWith("solver failed at t = 0.0005 s (step 1)"));
  CHECK(std::filesystem::exists(out / "output_000000.csv"));
}
