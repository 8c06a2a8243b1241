// Output formats of spec §10: CSV header and columns, VTK legacy ASCII read back.
#include <fstream>
#include <sstream>

#include <catch2/catch.hpp>

#include "core/io/geometry.hpp"
#include "core/io/output.hpp"
#include "core/run/driver.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

// A minimal reader of the VTK legacy ASCII unstructured grid we write: returns the points,
// the named point-data arrays, and checks the structural keywords on the way.
struct VtkData {
  std::vector<Vec2> points;
  std::map<std::string, std::vector<double>> scalars;
  std::vector<Vec2> velocity;
  double time = -1.0;
};

VtkData read_vtk(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string line, word;
  VtkData data;
  std::getline(file, line);
  REQUIRE(line == "# vtk DataFile Version 3.0");
  std::getline(file, line);  // title
  std::getline(file, line);
  REQUIRE(line == "ASCII");
  std::getline(file, line);
  REQUIRE(line == "DATASET UNSTRUCTURED_GRID");
  std::size_t n = 0;
  while (file >> word) {
    if (word == "FIELD") {
      std::string name, array;
      int arrays = 0, components = 0, tuples = 0;
      file >> name >> arrays >> array >> components >> tuples >> word >> data.time;
      REQUIRE(array == "TIME");
    } else if (word == "POINTS") {
      file >> n >> word;
      REQUIRE(word == "double");
      data.points.resize(n);
      for (auto& p : data.points) {
        double z = 1.0;
        file >> p.x() >> p.y() >> z;
        REQUIRE(z == 0.0);
      }
    } else if (word == "CELLS") {
      std::size_t cells = 0, size = 0;
      file >> cells >> size;
      REQUIRE(cells == n);
      REQUIRE(size == 2 * n);
      for (std::size_t k = 0; k < n; ++k) {
        std::size_t count = 0, index = 0;
        file >> count >> index;
        REQUIRE(count == 1);
        REQUIRE(index == k);
      }
    } else if (word == "CELL_TYPES") {
      std::size_t cells = 0;
      file >> cells;
      for (std::size_t k = 0; k < cells; ++k) {
        int kind = 0;
        file >> kind;
        REQUIRE(kind == 1);  // VTK_VERTEX
      }
    } else if (word == "POINT_DATA") {
      std::size_t count = 0;
      file >> count;
      REQUIRE(count == n);
    } else if (word == "SCALARS") {
      std::string name, type, lookup, table;
      int components = 0;
      file >> name >> type >> components >> lookup >> table;
      REQUIRE(components == 1);
      REQUIRE(lookup == "LOOKUP_TABLE");
      auto& values = data.scalars[name];
      values.resize(n);
      for (auto& v : values) file >> v;
    } else if (word == "VECTORS") {
      std::string name, type;
      file >> name >> type;
      REQUIRE(name == "velocity");
      data.velocity.resize(n);
      for (auto& v : data.velocity) {
        double z = 1.0;
        file >> v.x() >> v.y() >> z;
      }
    } else {
      FAIL("unexpected VTK keyword " << word);
    }
  }
  return data;
}

}  // namespace

TEST_CASE("frames: the spec's CSV and a VTK file that reads back - ghosts excluded", "[output]") {
  const auto out = fresh_directory("frames");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.output_directory = out.string();
  options.overrides = {"time.end_time=0.1"};
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  REQUIRE(result.steps == 200);

  // Frames every 100 steps: 0, 100, 200, each as CSV and VTK, 6-digit step numbers.
  for (const char* stem : {"output_000000", "output_000100", "output_000200"}) {
    CHECK(std::filesystem::exists(out / (std::string(stem) + ".csv")));
    CHECK(std::filesystem::exists(out / (std::string(stem) + ".vtk")));
  }
  CHECK_FALSE(std::filesystem::exists(out / "output_000300.csv"));
  // No temporary files left behind.
  for (const auto& entry : std::filesystem::directory_iterator(out)) {
    CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);
  }

  const std::string csv = read_text(out / "output_000100.csv");
  CHECK(csv.substr(0, csv.find('\n')) == "x,y,vx,vy,pressure,type");
  const Table table = read_table(out / "output_000100.csv");
  REQUIRE(table.rows.size() == 444);
  for (const auto& row : table.rows) {
    REQUIRE(row.size() == 6);
    CHECK((row[5] == 0.0 || row[5] == 1.0));
  }

  const VtkData vtk = read_vtk(out / "output_000100.vtk");
  REQUIRE(vtk.points.size() == 444);
  CHECK(vtk.time == Approx(0.05).epsilon(1e-12));
  REQUIRE(vtk.scalars.count("pressure") == 1);
  REQUIRE(vtk.scalars.count("type") == 1);
  CHECK(vtk.scalars.count("number_density") == 1);
  // The VTK frame holds the same particles and values as the CSV frame of the same step.
  const auto x = table.column("x"), p = table.column("pressure"), vx = table.column("vx");
  for (std::size_t k = 0; k < vtk.points.size(); ++k) {
    CHECK(vtk.points[k].x() == x[k]);
    CHECK(vtk.scalars.at("pressure")[k] == p[k]);
    CHECK(vtk.velocity[k].x() == vx[k]);
  }

  // series.csv: the required columns, a row every 10 steps, times consistent with dt.
  const Table series = read_table(out / "series.csv");
  for (const char* column :
       {"step", "time", "front", "height", "kinetic_energy", "solver_iterations", "solver_residual", "wall_seconds"}) {
    CHECK_NOTHROW(series.column(column));
  }
  CHECK(series.rows.size() == 21);
  CHECK(series.column("time")[20] == Approx(0.1).epsilon(1e-12));
  CHECK(series.column("front")[0] == Approx(0.225).epsilon(1e-12));
  CHECK(series.column("height")[0] == Approx(0.475).epsilon(1e-12));

  // The ParaView index lists every VTK frame with its time.
  const auto index = nlohmann::json::parse(read_text(out / "output.vtk.series"));
  CHECK(index["file-series-version"] == "1.0");
  REQUIRE(index["files"].size() == 3);
  CHECK(index["files"][1]["name"] == "output_000100.vtk");
  CHECK(index["files"][1]["time"].get<double>() == Approx(0.05).epsilon(1e-12));

  // run.json: what was run, how, and how it ended.
  const auto summary = nlohmann::json::parse(read_text(out / "run.json"));
  CHECK(summary["status"] == "completed");
  CHECK(summary["method"] == "mps");
  CHECK(summary["steps"] == 200);
  CHECK(summary["particles"]["fluid"] == 171);
  CHECK(summary["particles"]["wall"] == 273);
  CHECK(summary["parameters"]["relaxation"] == 0.2);
  CHECK(summary["wall_treatments"]["wall_repulsion"]["coefficient_factor"] == 0.5);
  CHECK(summary["method_summary"]["number_density_radius"]["n0"].get<double>() == Approx(6.5397).margin(5e-5));
  CHECK_FALSE(summary["git_revision"].get<std::string>().empty());
  CHECK(summary["wall_seconds"].get<double>() > 0.0);
}

TEST_CASE("a rerun into the same folder replaces the previous run's files and nothing else", "[output]") {
  const auto out = fresh_directory("rerun");
  write_text(out / "output_000900.csv", "stale\n");
  write_text(out / "notes.txt", "mine\n");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.output_directory = out.string();
  options.overrides = {"time.end_time=0.01"};
  REQUIRE(run_simulation(options, registries().methods, registries().walls).status == "completed");
  CHECK_FALSE(std::filesystem::exists(out / "output_000900.csv"));
  CHECK(read_text(out / "notes.txt") == "mine\n");
}

TEST_CASE("output by simulated time: a frame at the first step at or after each multiple", "[output]") {
  const auto out = fresh_directory("frame_interval");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.output_directory = out.string();
  // dt = 3e-4 s does not divide 0.01 s: frames fall at steps 34, 67, 100, 134, 167
  // (t = 0.0102, 0.0201, 0.03, 0.0402, 0.0501), plus step 0. Step counting is off (1e6).
  options.overrides = {"time.time_step=3e-4",          "output.frame_every_steps=1000000",
                       "output.frame_interval=0.01",   "output.series_every_steps=1000000",
                       "output.series_interval=0.002", "time.end_time=0.05"};
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  const auto index = nlohmann::json::parse(read_text(out / "output.vtk.series"));
  std::vector<std::string> names;
  for (const auto& file : index["files"]) names.push_back(file["name"]);
  CHECK(names == std::vector<std::string>{"output_000000.vtk", "output_000034.vtk", "output_000067.vtk",
                                          "output_000100.vtk", "output_000134.vtk", "output_000167.vtk"});
  // The series: a row at step 0 and at the first step at or after each 0.002 s (25 rows;
  // the 25th is the final step 167, t = 0.0501).
  const Table series = read_table(out / "series.csv");
  const auto time = series.column("time");
  CHECK(time.size() == 26);
  for (std::size_t k = 1; k < time.size(); ++k) {
    CHECK(time[k] >= 0.002 * static_cast<double>(k) - 1e-12);
    CHECK(time[k] < 0.002 * static_cast<double>(k) + 3e-4);
  }
}

TEST_CASE("a scene beyond the tested size runs - with a note in run.json", "[output]") {
  const auto out = fresh_directory("large_note");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.output_directory = out.string();
  // l0 = 0.0025: 99 x 199 = 19701 fluid particles, beyond the original 10000 (one step only).
  options.overrides = {"particle_spacing=0.0025", "time.time_step=1e-5", "time.end_time=1e-5"};
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  REQUIRE(result.summary["notes"].size() == 1);
  CHECK_THAT(result.summary["notes"][0].get<std::string>(), Catch::Contains("beyond the 10000"));
  options.overrides = {"time.end_time=1e-3"};
  CHECK(run_simulation(options, registries().methods, registries().walls).summary["notes"].empty());
}
