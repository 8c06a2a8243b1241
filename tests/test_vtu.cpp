// VTK XML binary frames (.vtu, appended raw data) and their ParaView collection (.pvd); the
// background frame writer: the same bytes as writing in the calling thread, and its failures
// reported as OutputErrors naming the file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <functional>
#include <map>
#include <random>
#include <regex>
#include <set>

#include "core/base/error.hpp"
#include "core/io/output.hpp"
#include "core/run/driver.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;
namespace fs = std::filesystem;

namespace {

// One DataArray of a VTU file: its attributes and the bytes of its appended block.
struct VtuArray {
  std::map<std::string, std::string> attributes;
  std::string bytes;
};

// A reader of the VTU files we write: the root element's attributes, the piece's sizes, every
// DataArray in order with its block. Checks the framing of the appended data on the way:
// offsets count from the byte after '_', each block is a UInt64 byte count and that many
// bytes, the blocks follow each other in the order of the arrays, and the last one ends
// where the AppendedData element closes.
struct VtuData {
  std::map<std::string, std::string> root;
  std::size_t points = 0;
  std::size_t cells = 0;
  std::vector<VtuArray> arrays;

  const VtuArray& array(const std::string& name) const {
    for (const auto& candidate : arrays) {
      if (candidate.attributes.at("Name") == name) return candidate;
    }
    FAIL("no DataArray " << name);
    return arrays.front();
  }
};

std::map<std::string, std::string> attributes_of(const std::string& tag) {
  static const std::regex attribute(R"re((\w+)="([^"]*)")re");
  std::map<std::string, std::string> result;
  for (std::sregex_iterator it(tag.begin(), tag.end(), attribute), end; it != end; ++it) {
    result[(*it)[1].str()] = (*it)[2].str();
  }
  return result;
}

VtuData read_vtu(const fs::path& path) {
  const std::string content = read_text(path);
  const std::string opening = "<AppendedData encoding=\"raw\">\n_";
  const std::size_t appended_at = content.find(opening);
  REQUIRE(appended_at != std::string::npos);
  const std::size_t base = appended_at + opening.size();
  const std::string xml = content.substr(0, appended_at);
  const std::string footer = "\n</AppendedData>\n</VTKFile>\n";
  REQUIRE(content.size() >= base + footer.size());
  REQUIRE(content.compare(content.size() - footer.size(), footer.size(), footer) == 0);

  VtuData data;
  std::smatch match;
  REQUIRE(std::regex_search(xml, match, std::regex("<VTKFile [^>]*>")));
  data.root = attributes_of(match.str());
  REQUIRE(std::regex_search(xml, match, std::regex("<Piece [^>]*>")));
  const auto piece = attributes_of(match.str());
  data.points = std::stoul(piece.at("NumberOfPoints"));
  data.cells = std::stoul(piece.at("NumberOfCells"));

  std::uint64_t expected_offset = 0;
  const std::regex data_array("<DataArray [^>]*/>");
  for (std::sregex_iterator it(xml.begin(), xml.end(), data_array), end; it != end; ++it) {
    VtuArray array;
    array.attributes = attributes_of(it->str());
    CHECK(array.attributes.at("format") == "appended");
    const std::uint64_t offset = std::stoull(array.attributes.at("offset"));
    CHECK(offset == expected_offset);
    REQUIRE(base + offset + sizeof(std::uint64_t) <= content.size());
    std::uint64_t size = 0;
    std::memcpy(&size, content.data() + base + offset, sizeof size);
    REQUIRE(base + offset + sizeof size + size <= content.size() - footer.size());
    array.bytes = content.substr(base + offset + sizeof size, size);
    expected_offset = offset + sizeof size + size;
    data.arrays.push_back(array);
  }
  CHECK(base + expected_offset == content.size() - footer.size());  // nothing unaccounted for
  return data;
}

template <typename T>
std::vector<T> values_of(const VtuArray& array) {
  REQUIRE(array.bytes.size() % sizeof(T) == 0);
  std::vector<T> values(array.bytes.size() / sizeof(T));
  std::memcpy(values.data(), array.bytes.data(), array.bytes.size());
  return values;
}

std::uint64_t bits_of(double value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// Fluid, wall and ghost particles with values that text would not keep (0.1, subnormals, -0,
// random bit patterns), a written field and one that is not written.
ParticleSet awkward_particles(std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  ParticleSet particles;
  const ParticleType kinds[] = {ParticleType::Fluid, ParticleType::Wall, ParticleType::Fluid, ParticleType::Ghost};
  for (int i = 0; i < 40; ++i) {
    particles.add(Vec2(uniform(random), uniform(random)), Vec2(uniform(random), 0.1 * i), kinds[i % 4]);
  }
  particles.position[0] = Vec2(0.1, 1e-310);
  particles.velocity[1] = Vec2(-0.0, 1.0 / 3.0);
  for (std::size_t i = 0; i < particles.size(); ++i) particles.pressure[i] = 1e5 * uniform(random);
  particles.pressure[2] = 5e-324;
  auto& density = particles.add_field("number_density");
  auto& hidden = particles.add_field("hidden");
  for (std::size_t i = 0; i < particles.size(); ++i) {
    density[i] = 6.5 + uniform(random);
    hidden[i] = 1.0;
  }
  return particles;
}

const std::vector<FieldSpec> kFields = {{"number_density", "", "", true}, {"hidden", "", "", false}};

std::string output_error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const OutputError& error) {
    return error.what();
  }
  return "no OutputError";
}

std::map<std::string, std::string> files_of(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::directory_iterator(folder))
    files[entry.path().filename().string()] = read_text(entry.path());
  return files;
}

}  // namespace

TEST_CASE("a VTU frame reads back bit for bit: header - appended blocks - offsets - UInt64 sizes", "[output]") {
  const auto out = fresh_directory("vtu_read_back");
  const ParticleSet particles = awkward_particles(7);
  const double time = 0.1;  // not a binary fraction: must come back bit for bit
  {
    RunOutput output(out, FrameFormats{false, false, true}, {"step"});
    output.prepare();
    output.write_frame(particles, kFields, time, 1234, "mps_lab test");
    output.flush();
  }
  CHECK_FALSE(fs::exists(out / "output_001234.csv"));
  CHECK_FALSE(fs::exists(out / "output_001234.vtk"));
  const VtuData vtu = read_vtu(out / "output_001234.vtu");
  CHECK(vtu.root.at("type") == "UnstructuredGrid");
  CHECK(vtu.root.at("version") == "1.0");
  CHECK(vtu.root.at("byte_order") == "LittleEndian");
  CHECK(vtu.root.at("header_type") == "UInt64");

  // The particles written: every one but the ghosts, in order.
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Ghost) kept.push_back(i);
  }
  const std::size_t n = kept.size();
  REQUIRE(n == 30);
  CHECK(vtu.points == n);
  CHECK(vtu.cells == n);

  std::vector<std::string> names;
  for (const auto& array : vtu.arrays) names.push_back(array.attributes.at("Name"));
  CHECK(names == std::vector<std::string>{"TIME", "pressure", "type", "velocity", "number_density", "Points",
                                          "connectivity", "offsets", "types"});

  const auto time_values = values_of<double>(vtu.array("TIME"));
  REQUIRE(time_values.size() == 1);
  CHECK(bits_of(time_values[0]) == bits_of(time));

  CHECK(vtu.array("Points").attributes.at("type") == "Float64");
  CHECK(vtu.array("Points").attributes.at("NumberOfComponents") == "3");
  const auto points = values_of<double>(vtu.array("Points"));
  CHECK(vtu.array("velocity").attributes.at("NumberOfComponents") == "3");
  const auto velocity = values_of<double>(vtu.array("velocity"));
  CHECK(vtu.array("pressure").attributes.at("type") == "Float64");
  const auto pressure = values_of<double>(vtu.array("pressure"));
  CHECK(vtu.array("type").attributes.at("type") == "Int32");
  const auto type = values_of<std::int32_t>(vtu.array("type"));
  const auto density = values_of<double>(vtu.array("number_density"));
  REQUIRE(points.size() == 3 * n);
  REQUIRE(velocity.size() == 3 * n);
  REQUIRE(pressure.size() == n);
  REQUIRE(type.size() == n);
  REQUIRE(density.size() == n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = kept[k];
    INFO("particle " << i);
    CHECK(bits_of(points[3 * k]) == bits_of(particles.position[i].x()));
    CHECK(bits_of(points[3 * k + 1]) == bits_of(particles.position[i].y()));
    CHECK(bits_of(points[3 * k + 2]) == bits_of(0.0));
    CHECK(bits_of(velocity[3 * k]) == bits_of(particles.velocity[i].x()));
    CHECK(bits_of(velocity[3 * k + 1]) == bits_of(particles.velocity[i].y()));
    CHECK(bits_of(velocity[3 * k + 2]) == bits_of(0.0));
    CHECK(bits_of(pressure[k]) == bits_of(particles.pressure[i]));
    CHECK(type[k] == static_cast<std::int32_t>(particles.type[i]));
    CHECK(bits_of(density[k]) == bits_of(particles.field("number_density")[i]));
  }
  // One VTK_VERTEX cell per point.
  const auto connectivity = values_of<std::int32_t>(vtu.array("connectivity"));
  const auto offsets = values_of<std::int32_t>(vtu.array("offsets"));
  const auto cell_types = values_of<std::uint8_t>(vtu.array("types"));
  REQUIRE(connectivity.size() == n);
  REQUIRE(offsets.size() == n);
  REQUIRE(cell_types.size() == n);
  for (std::size_t k = 0; k < n; ++k) {
    CHECK(connectivity[k] == static_cast<std::int32_t>(k));
    CHECK(offsets[k] == static_cast<std::int32_t>(k + 1));
    CHECK(cell_types[k] == 1);
  }
}

TEST_CASE("a frame without particles is a valid VTU file", "[output]") {
  const auto out = fresh_directory("vtu_empty");
  RunOutput output(out, FrameFormats{false, false, true}, {"step"});
  output.prepare();
  output.write_frame(ParticleSet{}, {}, 0.0, 0, "empty");
  output.flush();
  const VtuData vtu = read_vtu(out / "output_000000.vtu");
  CHECK(vtu.points == 0);
  CHECK(vtu.array("pressure").bytes.empty());
}

TEST_CASE("the .pvd collection lists every VTU frame with its time - rewritten as frames are added", "[output]") {
  const auto out = fresh_directory("vtu_pvd");
  ParticleSet particles = awkward_particles(3);
  RunOutput output(out, FrameFormats{false, true, true}, {"step"});
  output.prepare();
  const std::vector<std::pair<long long, double>> frames = {{0, 0.0}, {100, 0.05}, {233, 0.1 + 0.2}, {1000000, 7.0}};
  const auto listed = [&] {
    const std::string pvd = read_text(out / "output.pvd");
    CHECK(pvd.rfind("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\"", 0) == 0);
    std::vector<std::pair<std::string, double>> entries;
    const std::regex data_set(R"re(<DataSet timestep="([^"]*)" group="" part="0" file="([^"]*)"/>)re");
    for (std::sregex_iterator it(pvd.begin(), pvd.end(), data_set), end; it != end; ++it) {
      entries.emplace_back((*it)[2].str(), std::strtod((*it)[1].str().c_str(), nullptr));
    }
    return entries;
  };
  for (std::size_t k = 0; k < frames.size(); ++k) {
    output.write_frame(particles, kFields, frames[k].second, frames[k].first, "mps_lab test");
    output.flush();
    const auto entries = listed();
    REQUIRE(entries.size() == k + 1);
    for (std::size_t j = 0; j <= k; ++j) {
      CHECK(entries[j].first == frame_stem(frames[j].first) + ".vtu");
      CHECK(bits_of(entries[j].second) == bits_of(frames[j].second));  // the times read back exactly
      CHECK(fs::exists(out / entries[j].first));
    }
  }
  CHECK(frame_stem(1000000) + ".vtu" == "output_1000000.vtu");
  // The legacy index lists the same frames.
  const auto index = nlohmann::json::parse(read_text(out / "output.vtk.series"));
  REQUIRE(index["files"].size() == frames.size());
  CHECK(index["files"][2]["name"] == "output_000233.vtk");
}

TEST_CASE("frames written in the background are byte for byte those written in the calling thread", "[output]") {
  const auto background = fresh_directory("vtu_async");
  const auto in_caller = fresh_directory("vtu_sync");
  ParticleSet particles = awkward_particles(11);
  {
    RunOutput async_output(background, FrameFormats{true, true, true}, {"step", "time"}, FrameWriting::background);
    RunOutput sync_output(in_caller, FrameFormats{true, true, true}, {"step", "time"}, FrameWriting::in_caller);
    async_output.prepare();
    sync_output.prepare();
    std::mt19937_64 random(5);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (long long step = 0; step < 12; ++step) {
      const double time = 0.01 * static_cast<double>(step);
      sync_output.write_frame(particles, kFields, time, step, "mps_lab test");
      async_output.write_frame(particles, kFields, time, step, "mps_lab test");
      for (auto* output : {&sync_output, &async_output}) {
        output->add_series_row({static_cast<double>(step), time});
        output->write_series();
      }
      // The particles change at once, while the background frame is being written: it was copied.
      for (std::size_t i = 0; i < particles.size(); ++i) {
        particles.position[i] += 1e-3 * Vec2(uniform(random), uniform(random));
        particles.pressure[i] = uniform(random);
        particles.field("number_density")[i] = uniform(random);
      }
      particles.type[static_cast<std::size_t>(step)] = ParticleType::Ghost;  // the count changes too
    }
    CHECK(async_output.frames_written() == 12);
    CHECK(async_output.last_frame_step() == 11);
    async_output.write_summary({{"status", "completed"}});  // waits for the last frame
    sync_output.write_summary({{"status", "completed"}});
  }
  const auto expected = files_of(in_caller);
  const auto actual = files_of(background);
  CHECK(expected.size() == 12 * 3 + 4);  // frames, two indexes, series.csv, run.json
  REQUIRE(actual.size() == expected.size());
  for (const auto& [name, content] : expected) {
    INFO(name);
    REQUIRE(actual.count(name) == 1);
    CHECK(actual.at(name) == content);
  }
}

TEST_CASE("series.csv is rewritten at most once per period during a run - and whole by write_summary", "[output]") {
  // A run rewrites the whole file (atomically), so a rewrite after every row cost O(rows^2): 89-90 % of
  // a 23,000-step run with a row per step (core/io/output.hpp, kSeriesRewritePeriod, 1 s). With a
  // period of an hour the first row is written at once and the next 199 wait; run.json's
  // write_summary writes all 200 (as a checkpoint's, the run's end and a stop do). With a period of
  // 0 every row is written as it comes.
  for (const long long period_ms : {3600000LL, 0LL}) {
    INFO("period " << period_ms << " ms");
    const auto dir = fresh_directory("series_period_" + std::to_string(period_ms));
    RunOutput output(dir, FrameFormats{true, false, false}, {"step"});
    output.set_series_rewrite_period(std::chrono::milliseconds(period_ms));
    output.prepare();
    const auto rows_on_disk = [&] {
      const std::string text = read_text(dir / "series.csv");
      return std::count(text.begin(), text.end(), '\n') - 1;  // without the header
    };
    for (int step = 0; step < 200; ++step) {
      output.add_series_row({static_cast<double>(step)});
      output.write_series_when_due();
    }
    CHECK(rows_on_disk() == (period_ms > 0 ? 1 : 200));
    output.write_summary({{"status", "completed"}});
    CHECK(rows_on_disk() == 200);
    const std::string text = read_text(dir / "series.csv");
    CHECK(text.substr(text.size() - 4) == "199\n");
  }
}

TEST_CASE("a background write that fails is a one-line OutputError naming the file at the next call", "[output]") {
  const auto dir = fresh_directory("vtu_async_failure");
  const ParticleSet particles = awkward_particles(1);
  // The folder disappears after prepare(): the frame cannot be created (as root too, unlike a
  // permission check).
  {
    RunOutput output(dir / "run", FrameFormats{false, false, true}, {"step"});
    output.prepare();
    fs::remove_all(dir / "run");
    output.write_frame(particles, kFields, 0.0, 0, "t");  // handed over; fails in the background
    const std::string expected =
        (dir / "run" / "output_000000.vtu").string() + ": cannot write (No such file or directory)";
    // The next frame waits for the first and reports its failure.
    CHECK(output_error_of([&] { output.write_frame(particles, kFields, 0.1, 1, "t"); }) == expected);
    // It stays reported: every later call, flush and the end of the run, says the same.
    CHECK(output_error_of([&] { output.add_series_row({1.0}); }) == expected);
    CHECK(output_error_of([&] { output.write_series(); }) == expected);
    CHECK(output_error_of([&] { output.flush(); }) == expected);
    CHECK(output_error_of([&] { output.write_summary({}); }) == expected);
    CHECK(output.frames_written() == 1);  // the second frame was refused
  }                                       // the destructor waits and does not throw
  {
    RunOutput output(dir / "run2", FrameFormats{true, true, false}, {"step"});
    output.prepare();
    fs::remove_all(dir / "run2");
    output.write_frame(particles, kFields, 0.0, 0, "t");
    const std::string message = output_error_of([&] { output.flush(); });
    CHECK(message == (dir / "run2" / "output_000000.csv").string() + ": cannot write (No such file or directory)");
    CHECK(message.find('\n') == std::string::npos);
  }
  {
    // In the calling thread, the write_frame call itself fails.
    RunOutput output(dir / "run3", FrameFormats{false, true, false}, {"step"}, FrameWriting::in_caller);
    output.prepare();
    fs::remove_all(dir / "run3");
    CHECK(output_error_of([&] { output.write_frame(particles, kFields, 0.0, 0, "t"); }) ==
          (dir / "run3" / "output_000000.vtk").string() + ": cannot write (No such file or directory)");
  }
  {
    // The destructor of an output with a frame in flight waits for it.
    RunOutput output(dir / "run4", FrameFormats{true, true, true}, {"step"});
    output.prepare();
    output.write_frame(particles, kFields, 0.0, 0, "t");
  }
  for (const char* name :
       {"output_000000.csv", "output_000000.vtk", "output_000000.vtu", "output.pvd", "output.vtk.series"}) {
    CHECK(fs::exists(dir / "run4" / name));
  }
}

TEST_CASE("a run with VTU frames: each reads back as its CSV frame - and the scene validates the format list",
          "[output]") {
  const auto out = fresh_directory("vtu_run");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.output_directory = out.string();
  options.overrides = {"time.end_time=0.1", "output.formats=[\"csv\", \"vtu\"]"};
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  CHECK(result.summary["frames"] == 3);
  CHECK_FALSE(fs::exists(out / "output_000100.vtk"));
  CHECK_FALSE(fs::exists(out / "output.vtk.series"));
  for (const auto& entry : fs::directory_iterator(out)) {
    CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);
  }
  const Table table = read_table(out / "output_000100.csv");
  const VtuData vtu = read_vtu(out / "output_000100.vtu");
  REQUIRE(vtu.points == table.rows.size());
  const auto points = values_of<double>(vtu.array("Points"));
  const auto velocity = values_of<double>(vtu.array("velocity"));
  const auto pressure = values_of<double>(vtu.array("pressure"));
  const auto x = table.column("x"), y = table.column("y"), vy = table.column("vy"), p = table.column("pressure");
  for (std::size_t k = 0; k < vtu.points; ++k) {
    // The CSV's shortest round-trip text reads back to the same doubles.
    CHECK(points[3 * k] == x[k]);
    CHECK(points[3 * k + 1] == y[k]);
    CHECK(velocity[3 * k + 1] == vy[k]);
    CHECK(pressure[k] == p[k]);
  }
  const std::string pvd = read_text(out / "output.pvd");
  CHECK_THAT(pvd, Catch::Contains(R"(<DataSet timestep="0.05" group="" part="0" file="output_000100.vtu"/>)"));

  // A rerun removes the VTU frames and the collection of the previous one.
  write_text(out / "output_000900.vtu", "stale\n");
  options.overrides = {"time.end_time=0.01", "output.formats=[\"csv\"]"};
  REQUIRE(run_simulation(options, registries().methods, registries().walls).status == "completed");
  CHECK_FALSE(fs::exists(out / "output_000900.vtu"));
  CHECK_FALSE(fs::exists(out / "output_000000.vtu"));
  CHECK_FALSE(fs::exists(out / "output.pvd"));

  const Scene scene = load("dambreak.json", {"output.formats=[\"vtu\"]"});
  CHECK(scene.output.vtu);
  CHECK_FALSE(scene.output.vtk);
  CHECK_FALSE(scene.output.csv);
  CHECK_THROWS_AS(load("dambreak.json", {"output.formats=[\"vtx\"]"}), InputError);
}

TEST_CASE("VTU frames and their collection resume bit for bit after an interruption", "[output][checkpoint]") {
  const auto full = fresh_directory("vtu_resume_full");
  const auto part = fresh_directory("vtu_resume_part");
  const auto run = [](const fs::path& folder, long long stop_after) {
    RunOptions options;
    options.scene_path = scene_path("dambreak.json");
    options.output_directory = folder.string();
    options.overrides = {"time.end_time=0.1", "output.formats=[\"vtk\", \"vtu\"]"};
    auto polls = std::make_shared<long long>(0);
    if (stop_after > 0) {
      options.stop_reason = [polls, stop_after] { return ++*polls >= stop_after ? "a test" : ""; };
    }
    return run_simulation(options, registries().methods, registries().walls);
  };
  REQUIRE(run(full, 0).status == "completed");
  REQUIRE(run(part, 137).status == "interrupted");
  CHECK(fs::exists(part / "output_000137.vtu"));  // the interruption's extra frame
  RunOptions resume;
  resume.resume_directory = part;
  REQUIRE(run_simulation(resume, registries().methods, registries().walls).status == "completed");
  CHECK_FALSE(fs::exists(part / "output_000137.vtu"));  // removed by resume
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(full)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("output", 0) != 0) continue;
    names.insert(name);
    INFO(name);
    CHECK(read_text(part / name) == read_text(entry.path()));
  }
  CHECK(names == std::set<std::string>{"output_000000.vtk", "output_000100.vtk", "output_000200.vtk",
                                       "output_000000.vtu", "output_000100.vtu", "output_000200.vtu",
                                       "output.vtk.series", "output.pvd"});
}
