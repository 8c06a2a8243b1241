#include "lab/benchmark.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>

#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include "core/base/error.hpp"
#include "core/base/memory_bytes.hpp"
#include "core/io/geometry.hpp"
#include "core/io/output.hpp"
#include "core/io/scene.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/run/driver.hpp"
#include "core/search/neighbour_search.hpp"
#include "methods/mps/mps_kernels.hpp"

namespace mps_lab {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Repeats `work` until it has taken at least 0.2 s (and at least 3 times); the fastest time.
template <typename Work>
double fastest_seconds(Work&& work) {
  double fastest = 1e300, total = 0.0;
  for (int repeat = 0; repeat < 3 || (total < 0.2 && repeat < 1000); ++repeat) {
    const auto start = Clock::now();
    work();
    const double seconds = seconds_since(start);
    fastest = std::min(fastest, seconds);
    total += seconds;
  }
  return fastest;
}

std::size_t count_fluid(const ParticleSet& particles) { return particles.count(ParticleType::Fluid); }

// The kernels alone on the scene's initial particles (wall particles included, as the spec's
// walls have them): search at 2.1 l0, MPS number density (spec §2), SPH summation density.
nlohmann::json kernel_case(const Scene& scene) {
  const ParticleSet particles = build_particles(scene, true);
  const double l0 = scene.particle_spacing;
  const double re = 2.1 * l0;
  const std::size_t n = particles.size();
  CellList cells;
  NeighbourList neighbours;
  const double search_seconds = fastest_seconds([&] {
    cells.build(particles.position, particles.type, re);
    cells.find_neighbours(particles.position, particles.type, re, neighbours);
  });
  std::vector<double> out(n, 0.0);
  const auto count = static_cast<std::ptrdiff_t>(n);
  const double r_min = 0.01 * l0;
  const double number_density_seconds = fastest_seconds([&] {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {  // n_i = sum_j w(|r_ij|, re)  (spec §2)
      double sum = 0.0;
      const auto p = static_cast<std::size_t>(i);
      for (std::uint32_t k = neighbours.begin(p); k < neighbours.end(p); ++k) {
        sum += mps_weight((particles.position[neighbours.indices[k]] - particles.position[p]).norm(), re, r_min);
      }
      out[p] = sum;
    }
  });
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.4 * l0);  // h = 1.2 l0, support 2h
  const double mass = scene.physics.density / lattice_kernel_sum(kernel, l0);
  const double density_seconds = fastest_seconds([&] {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {  // rho_i = sum_j m W(|r_ij|, h), self included
      const auto p = static_cast<std::size_t>(i);
      double sum = kernel.value(0.0);
      for (std::uint32_t k = neighbours.begin(p); k < neighbours.end(p); ++k) {
        const double r = (particles.position[neighbours.indices[k]] - particles.position[p]).norm();
        if (r < kernel.support()) sum += kernel.value(r);
      }
      out[p] = mass * sum;
    }
  });
  const double per_particle = 1e9 / static_cast<double>(n);
  return {{"kind", "kernels"},
          {"particles", n},
          {"fluid_particles", count_fluid(particles)},
          {"mean_neighbours", static_cast<double>(neighbours.indices.size()) / static_cast<double>(n)},
          {"neighbour_search_ns_per_particle", search_seconds * per_particle},
          {"number_density_ns_per_particle", number_density_seconds * per_particle},
          {"sph_density_ns_per_particle", density_seconds * per_particle}};
}

const char* main_solver_phase(const nlohmann::json& phases) {
  if (phases.contains("pressure_solve")) return "pressure_solve";
  if (phases.contains("density_solve")) return "density_solve";
  return nullptr;
}

// The heap the particles hold (capacities of their arrays and fields), bytes.
std::size_t particle_bytes(const ParticleSet& particles) {
  std::size_t bytes =
      held_bytes(particles.position, particles.velocity, particles.pressure, particles.type, particles.wall_layer,
                 particles.wall_velocity, particles.wall_acceleration, particles.id);
  for (const auto& field : particles.scalar_fields) bytes += held_bytes(field.second);
  return bytes;
}

// The memory breakdown of a case (bytes per particle): the particles and the method's own
// (Method::memory_breakdown), and their sum ("accounted"): what the resident figure has beyond
// it is the rest of the Simulation (wall treatments, diagnostics, moving walls) and the
// allocator's pages.
void add_memory_breakdown(const Simulation& simulation, nlohmann::json& result) {
  const auto n = static_cast<double>(simulation.particles().size());
  nlohmann::json breakdown = nlohmann::json::object();
  double accounted = 0.0;
  const auto add = [&](const std::string& name, std::size_t bytes) {
    breakdown[name] = static_cast<double>(bytes) / n;
    accounted += static_cast<double>(bytes);
  };
  add("particles", particle_bytes(simulation.particles()));
  for (const auto& [name, bytes] : simulation.method().memory_breakdown()) add(name, bytes);
  result["memory_breakdown_bytes_per_particle"] = breakdown;
  result["memory_accounted_bytes_per_particle"] = accounted / n;
}

nlohmann::json method_case(const Scene& scene, const MethodInfo& info, const BenchmarkOptions& options) {
  const std::size_t memory_before = resident_memory_bytes();
  Simulation simulation(scene, info);
  const std::size_t fluid = count_fluid(simulation.particles());
  nlohmann::json result = {{"kind", "steps"},
                           {"method", info.name},
                           {"particles", simulation.particles().size()},
                           {"fluid_particles", fluid}};
  try {
    if (options.start_time > 0.0) simulation.run_to(options.start_time);
    for (long long step = 0; step < options.warmup_steps; ++step) simulation.advance();
    simulation.timers().reset();
    const double measured_from = simulation.time();
    long long iterations = 0;
    const auto start = Clock::now();
    for (long long step = 0; step < options.steps; ++step) iterations += simulation.advance().solver_iterations;
    const double seconds = seconds_since(start);
    const std::size_t memory_after = resident_memory_bytes();
    const nlohmann::json profile = profile_json(simulation.timers(), seconds, options.steps, fluid);
    result["status"] = "completed";
    result["start_time"] = measured_from;
    result["seconds"] = seconds;
    result["steps"] = options.steps;
    result["time_step"] = simulation.last_time_step();
    result["fluid_particle_steps_per_second"] = profile["fluid_particle_steps_per_second"];
    result["milliseconds_per_step"] = 1e3 * seconds / static_cast<double>(options.steps);
    result["nanoseconds_per_particle_step"] =
        1e9 * seconds / (static_cast<double>(options.steps) * static_cast<double>(fluid));
    result["mean_solver_iterations"] = static_cast<double>(iterations) / static_cast<double>(options.steps);
    result["phases"] = profile["phases"];
    if (const char* phase = main_solver_phase(profile["phases"]); phase != nullptr && iterations > 0) {
      result["solver_phase"] = phase;
      result["solver_iteration_microseconds"] =
          1e6 * profile["phases"][phase]["seconds"].get<double>() / static_cast<double>(iterations);
    }
    const double held = static_cast<double>(memory_after) - static_cast<double>(memory_before);
    result["memory_bytes_per_particle"] = std::max(0.0, held) / static_cast<double>(simulation.particles().size());
    add_memory_breakdown(simulation, result);
  } catch (const std::exception& error) {
    result["status"] = "failed";
    result["message"] = error.what();
  }
  return result;
}

std::string fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

// One line per completed case with a breakdown: the resident figure, the accounted sum and
// every structure of at least 1 B per particle, largest first.
std::string memory_table(const nlohmann::json& results) {
  std::string out;
  for (const auto& c : results.at("cases")) {
    if (c.at("kind") != "steps" || !c.contains("memory_breakdown_bytes_per_particle")) continue;
    if (out.empty()) out = "\nmemory, B/particle (resident; accounted = the capacities below)\n";
    std::vector<std::pair<double, std::string>> items;
    for (const auto& item : c.at("memory_breakdown_bytes_per_particle").items())
      items.emplace_back(item.value().get<double>(), item.key());
    std::sort(items.rbegin(), items.rend());
    out += c.at("method").get<std::string>() + " l0 " + fixed(c.at("particle_spacing").get<double>(), 5) + " thr " +
           std::to_string(c.at("threads").get<int>()) + ": resident " +
           fixed(c.at("memory_bytes_per_particle").get<double>(), 0) + ", accounted " +
           fixed(c.at("memory_accounted_bytes_per_particle").get<double>(), 0) + ":";
    for (const auto& [bytes, name] : items)
      if (bytes >= 1.0) out += " " + name + " " + fixed(bytes, bytes < 10.0 ? 1 : 0) + ",";
    out.back() = '\n';
  }
  return out;
}

}  // namespace

nlohmann::json run_benchmarks(const BenchmarkOptions& options, const MethodRegistry& methods,
                              const WallTreatmentRegistry& walls) {
  std::vector<const MethodInfo*> chosen;
  if (options.methods.empty()) {
    chosen = methods.all();
  } else {
    for (const auto& name : options.methods) {
      const MethodInfo* info = methods.find(name);
      if (info == nullptr) throw_input_error("--methods", name, "unknown method");
      chosen.push_back(info);
    }
  }
  std::vector<double> spacings = options.spacings;
  if (spacings.empty()) spacings.push_back(0.0);  // the scene's own
  std::vector<int> thread_counts = options.threads;
  if (thread_counts.empty()) thread_counts.push_back(omp_get_max_threads());
  const int threads_before = omp_get_max_threads();

  nlohmann::json cases = nlohmann::json::array();
  for (double spacing : spacings) {
    std::vector<std::string> overrides = options.overrides;
    if (spacing > 0.0) {
      overrides.push_back("particle_spacing=" + format_double(spacing));
      if (options.time_step_per_spacing > 0.0) {
        overrides.push_back("time.time_step=" + format_double(options.time_step_per_spacing * spacing));
      }
      for (const auto& item : options.per_spacing) {
        const auto equals = item.find('=');
        double factor = 0.0;
        try {
          factor = equals == std::string::npos ? 0.0 : std::stod(item.substr(equals + 1));
        } catch (const std::exception&) {
          factor = 0.0;
        }
        if (!(factor > 0.0))
          throw_input_error("--per-spacing", item, "expected KEY=FACTOR with a factor > 0 (s/m, ...)");
        overrides.push_back(item.substr(0, equals) + "=" + format_double(factor * spacing));
      }
    }
    const Scene scene = load_scene(options.scene_path, overrides, methods, walls);
    for (int threads : thread_counts) {
      omp_set_num_threads(threads);
      const auto tag = [&](nlohmann::json result) {
        result["particle_spacing"] = scene.particle_spacing;
        result["threads"] = threads;
        if (options.progress) std::fprintf(stderr, "mps_lab bench: %s\n", result.dump().c_str());
        cases.push_back(std::move(result));
      };
      if (options.kernels) tag(kernel_case(scene));
      for (const MethodInfo* info : chosen) tag(method_case(scene, *info, options));
    }
  }
  omp_set_num_threads(threads_before);
  return {{"scene", options.scene_path},
          {"warmup_steps", options.warmup_steps},
          {"steps", options.steps},
          {"start_time", options.start_time},
          {"time_step_per_spacing", options.time_step_per_spacing},
          {"per_spacing", options.per_spacing},
          {"peak_resident_bytes", peak_resident_memory_bytes()},
          {"cases", cases}};
}

std::string benchmark_table(const nlohmann::json& results) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-6s %8s %3s %9s %12s %9s %8s %9s %8s  %s\n", "method", "l0", "thr", "fluid",
                "p-steps/s", "ms/step", "iter", "us/iter", "B/part", "ms/step per phase");
  out += line;
  for (const auto& c : results.at("cases")) {
    if (c.at("kind") != "steps") continue;
    if (c.at("status") != "completed") {
      std::snprintf(line, sizeof line, "%-6s %8.5f %3d %9zu  %s\n", c.at("method").get<std::string>().c_str(),
                    c.at("particle_spacing").get<double>(), c.at("threads").get<int>(),
                    c.at("fluid_particles").get<std::size_t>(), c.value("message", std::string()).c_str());
      out += line;
      continue;
    }
    std::vector<std::pair<double, std::string>> phases;
    for (const auto& item : c.at("phases").items()) {
      phases.emplace_back(item.value().at("milliseconds_per_step").get<double>(), item.key());
    }
    std::sort(phases.rbegin(), phases.rend());
    std::string breakdown;
    for (const auto& [ms, name] : phases) {
      if (ms <= 0.0) continue;
      breakdown += (breakdown.empty() ? "" : ", ") + name + " " + (ms < 1.0 ? fixed(ms, 3) : fixed(ms, 2));
    }
    std::snprintf(line, sizeof line, "%-6s %8.5f %3d %9zu %12.4g %9.3f %8.1f %9.2f %8.0f  %s\n",
                  c.at("method").get<std::string>().c_str(), c.at("particle_spacing").get<double>(),
                  c.at("threads").get<int>(), c.at("fluid_particles").get<std::size_t>(),
                  c.at("fluid_particle_steps_per_second").get<double>(), c.at("milliseconds_per_step").get<double>(),
                  c.at("mean_solver_iterations").get<double>(), c.value("solver_iteration_microseconds", 0.0),
                  c.at("memory_bytes_per_particle").get<double>(), breakdown.c_str());
    out += line;
  }
  out += memory_table(results);
  bool header = false;
  for (const auto& c : results.at("cases")) {
    if (c.at("kind") != "kernels") continue;
    if (!header) {
      std::snprintf(line, sizeof line, "\n%-8s %3s %9s %10s %18s %18s %18s\n", "l0", "thr", "particles", "neighbours",
                    "search ns/part", "n_i ns/part", "rho_i ns/part");
      out += line;
      header = true;
    }
    std::snprintf(
        line, sizeof line, "%8.5f %3d %9zu %10.2f %18.1f %18.1f %18.1f\n", c.at("particle_spacing").get<double>(),
        c.at("threads").get<int>(), c.at("particles").get<std::size_t>(), c.at("mean_neighbours").get<double>(),
        c.at("neighbour_search_ns_per_particle").get<double>(), c.at("number_density_ns_per_particle").get<double>(),
        c.at("sph_density_ns_per_particle").get<double>());
    out += line;
  }
  return out;
}

}  // namespace mps_lab
