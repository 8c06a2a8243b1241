// Determinism (docs/architecture.md): the same scene and thread count give byte-identical
// output, and so far no result depends on the thread count either: every parallel loop
// writes only its own particle, neighbour lists are built in a fixed order, and no sum is
// split across threads (see the per-method [determinism] tests for the particle arrays).
// Here the whole output of a run is compared: every frame file and series.csv without its
// wall_seconds column.
#include <omp.h>

#include <catch2/catch.hpp>

#include "core/run/driver.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

std::filesystem::path run_with_threads(const std::string& method, int threads, const std::string& tag) {
  const int previous = omp_get_max_threads();
  omp_set_num_threads(threads);
  const auto out = fresh_directory("determinism_" + method + "_" + tag);
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.method = method;
  options.output_directory = out.string();
  // l0 = 0.0125 m (1,278 particles): above the size at which the methods' loops use threads.
  options.overrides = {"particle_spacing=0.0125", "time.end_time=0.06", "output.frame_interval=0.01"};
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  omp_set_num_threads(previous);
  REQUIRE(result.status == "completed");
  return out;
}

// series.csv without the wall_seconds column (the one thing that must differ).
std::string series_without_wall_time(const std::filesystem::path& dir) {
  const Table table = read_table(dir / "series.csv");
  std::string text;
  for (const auto& row : table.rows) {
    for (std::size_t k = 0; k < row.size(); ++k) {
      if (table.header[k] != "wall_seconds") text += std::to_string(row[k]) + ",";
    }
    text += "\n";
  }
  return text;
}

void check_identical(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::size_t frames = 0;
  for (const auto& entry : std::filesystem::directory_iterator(a)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("output_", 0) != 0) continue;
    INFO(name);
    CHECK(read_text(entry.path()) == read_text(b / name));
    ++frames;
  }
  CHECK(frames >= 14);  // 7 frames (t = 0, 0.01, ..., 0.06) in CSV and VTK
  CHECK(series_without_wall_time(a) == series_without_wall_time(b));
}

}  // namespace

TEST_CASE("same scene, same thread count: byte-identical frames and series, every method", "[determinism]") {
  for (const std::string method : {"mps", "isph", "dfsph"}) {
    INFO(method);
    check_identical(run_with_threads(method, 2, "first"), run_with_threads(method, 2, "second"));
  }
}

TEST_CASE("one and two threads: byte-identical frames and series, every method", "[determinism]") {
  for (const std::string method : {"mps", "isph", "dfsph"}) {
    INFO(method);
    check_identical(run_with_threads(method, 1, "one"), run_with_threads(method, 2, "two"));
  }
}
